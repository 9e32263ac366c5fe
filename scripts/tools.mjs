// Installs what the project needs and is missing, idempotently: the wasm32
// target, pinned wasm-pack and wasm-bindgen-cli, the npm dependencies and (for
// the browser tests) Debian's Chromium, (for the batch test) Debian's Slurm.
// Each step checks versions first and costs well under a second when
// everything is present. A step that cannot install prints what is missing
// and how to install it by hand.
//
//   node scripts/tools.mjs [--browser] [--slurm]
import fs from 'node:fs';
import path from 'node:path';
import { repo, run, capture } from './lib.mjs';

export const WASM_PACK = '0.15.1';
export const WASM_BINDGEN = '0.2.130';
export const CHROMIUM = '/usr/lib/chromium/chromium';

class MissingTool extends Error {}

function fail(what, howto) {
  throw new MissingTool(`${what}\n  To install it by hand:\n    ${howto.join('\n    ')}`);
}

function versionOf(cmd) {
  const r = capture(cmd, ['--version']);
  return r.status === 0 ? r.stdout.trim() : null;
}

function ensureRust() {
  if (versionOf('cargo') === null) {
    fail('cargo (Rust) is not installed.', ["curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs | sh", '(or your distribution\'s rustup package)']);
  }
  const installed = capture('rustup', ['target', 'list', '--installed']);
  if (installed.status === 127) {
    fail('rustup is not available to add the wasm32-unknown-unknown target.', ['install Rust through rustup, then: rustup target add wasm32-unknown-unknown']);
  }
  if (!installed.stdout.split('\n').includes('wasm32-unknown-unknown')) {
    console.log('tools: adding the Rust target wasm32-unknown-unknown');
    if (run('rustup', ['target', 'add', 'wasm32-unknown-unknown']) !== 0) {
      fail('could not add the wasm32-unknown-unknown target.', ['rustup target add wasm32-unknown-unknown']);
    }
  }
}

function ensureCargoTool(cmd, crate, version, locked) {
  const have = versionOf(cmd);
  if (have !== null && have.split(/\s+/)[1] === version) return;
  console.log(`tools: installing ${crate} ${version} (found: ${have ?? 'none'}); this takes a few minutes once`);
  const args = ['install', crate, '--version', version, '--force'];
  if (locked) args.push('--locked');
  if (run('cargo', args) !== 0 || versionOf(cmd)?.split(/\s+/)[1] !== version) {
    fail(`${crate} ${version} could not be installed.`, [`cargo install ${crate} --version ${version}${locked ? ' --locked' : ''}`]);
  }
}

function ensureNpm() {
  const lock = JSON.parse(fs.readFileSync(path.join(repo, 'package-lock.json'), 'utf8'));
  const wanted = Object.entries(lock.packages ?? {}).filter(([k, v]) => k.startsWith('node_modules/') && !v.optional);
  const missing = wanted.filter(([k, v]) => {
    try {
      return JSON.parse(fs.readFileSync(path.join(repo, k, 'package.json'), 'utf8')).version !== v.version;
    } catch {
      return true;
    }
  });
  if (missing.length === 0) return;
  console.log(`tools: installing npm dependencies (${missing.length} missing or outdated)`);
  if (run('npm', ['ci', '--no-audit', '--no-fund']) !== 0) {
    fail('npm ci failed.', ['npm ci']);
  }
}

/**
 * Installs Debian packages when `present()` is false: as root with apt-get,
 * else it fails with the command to run by hand.
 */
function ensureDebian(what, present, packages, howto) {
  if (present()) return;
  const isRoot = typeof process.getuid === 'function' && process.getuid() === 0;
  const hasApt = capture('apt-get', ['--version']).status === 0;
  if (isRoot && hasApt) {
    console.log(`tools: installing Debian's ${packages.join(', ')} for ${what}`);
    const env = { DEBIAN_FRONTEND: 'noninteractive' };
    const install = ['install', '-y', '-qq', '--no-install-recommends', ...packages];
    if (run('apt-get', ['update', '-qq']) === 0 && run('apt-get', install, { env }) === 0 && present()) return;
  }
  fail(`${what}: ${packages.join(', ')} missing.`, [`sudo apt-get update && sudo apt-get install -y ${packages.join(' ')}`, ...howto]);
}

function ensureChromium() {
  ensureDebian('the browser tests (Chromium)', () => fs.existsSync(CHROMIUM), ['chromium'], [
    '(Debian/Ubuntu; elsewhere install Chromium and set CHROMIUM_PATH=/path/to/the/chromium/binary)',
  ]);
}

/** Slurm's controller, node daemon and client commands, for the batch layer. */
export const SLURM_COMMANDS = ['slurmctld', 'slurmd', 'sbatch', 'squeue', 'scontrol', 'sinfo'];

/**
 * The path of a command on PATH or in /usr/sbin (where Debian puts the
 * daemons), or null. Slurm's client commands need a configuration even for
 * `--version`, so presence is looked up rather than run.
 */
export function commandPath(cmd) {
  const dirs = [...(process.env.PATH ?? '').split(path.delimiter), '/usr/sbin', '/usr/local/sbin'];
  for (const dir of dirs) {
    const file = path.join(dir, cmd);
    try {
      fs.accessSync(file, fs.constants.X_OK);
      return file;
    } catch {
      // not here
    }
  }
  return null;
}

function ensureSlurm() {
  const present = () => SLURM_COMMANDS.every((c) => commandPath(c) !== null);
  ensureDebian('the batch test (a real Slurm on localhost)', present, ['slurmctld', 'slurmd', 'slurm-client'], [
    '(Debian/Ubuntu; elsewhere any Slurm 22 or later with slurmctld, slurmd and the client commands on PATH)',
  ]);
}

/**
 * Ensures every tool; `browser` adds Chromium, `slurm` Slurm. Returns false
 * (after printing why) on failure.
 */
export function ensureTools({ browser = false, slurm = false } = {}) {
  try {
    ensureRust();
    ensureCargoTool('wasm-pack', 'wasm-pack', WASM_PACK, true);
    // Without --locked: its lock file pins a crate version the registry lacks.
    ensureCargoTool('wasm-bindgen', 'wasm-bindgen-cli', WASM_BINDGEN, false);
    ensureNpm();
    if (browser && !process.env.CHROMIUM_PATH) ensureChromium();
    if (slurm) ensureSlurm();
    return true;
  } catch (e) {
    if (e instanceof MissingTool) {
      console.error(`tools: ${e.message}`);
      return false;
    }
    throw e;
  }
}

if (process.argv[1] && path.resolve(process.argv[1]) === path.join(repo, 'scripts', 'tools.mjs')) {
  process.exit(ensureTools({ browser: process.argv.includes('--browser'), slurm: process.argv.includes('--slurm') }) ? 0 : 1);
}
