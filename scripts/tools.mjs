// Installs what the project needs and is missing, idempotently: the wasm32
// target, pinned wasm-pack and wasm-bindgen-cli, the npm dependencies and (for
// the browser tests) Debian's Chromium. Each step checks versions first and
// costs well under a second when everything is present. A step that cannot
// install prints what is missing and how to install it by hand.
//
//   node scripts/tools.mjs [--browser]
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

function ensureChromium() {
  if (fs.existsSync(CHROMIUM)) return;
  const isRoot = typeof process.getuid === 'function' && process.getuid() === 0;
  const hasApt = capture('apt-get', ['--version']).status === 0;
  if (isRoot && hasApt) {
    console.log('tools: installing Debian\'s chromium for the browser tests');
    if (run('apt-get', ['update', '-qq']) === 0 && run('apt-get', ['install', '-y', '-qq', 'chromium'], { env: { DEBIAN_FRONTEND: 'noninteractive' } }) === 0 && fs.existsSync(CHROMIUM)) {
      return;
    }
  }
  fail(`Chromium is missing (${CHROMIUM}); the browser tests drive it.`, [
    'sudo apt-get update && sudo apt-get install -y chromium',
    '(Debian/Ubuntu; elsewhere install Chromium and set CHROMIUM_PATH=/path/to/the/chromium/binary)',
  ]);
}

/** Ensures every tool; `browser` adds Chromium. Returns false (after printing why) on failure. */
export function ensureTools({ browser = false } = {}) {
  try {
    ensureRust();
    ensureCargoTool('wasm-pack', 'wasm-pack', WASM_PACK, true);
    // Without --locked: its lock file pins a crate version the registry lacks.
    ensureCargoTool('wasm-bindgen', 'wasm-bindgen-cli', WASM_BINDGEN, false);
    ensureNpm();
    if (browser && !process.env.CHROMIUM_PATH) ensureChromium();
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
  process.exit(ensureTools({ browser: process.argv.includes('--browser') }) ? 0 : 1);
}
