// `npm test`: installs what is missing, then runs every test layer and prints
// one summary line per layer. Exits non-zero when any layer fails.
//
//   node scripts/test.mjs [--only fmt,clippy,...]
import fs from 'node:fs';
import path from 'node:path';
import { repo, run, seconds } from './lib.mjs';
import { ensureTools } from './tools.mjs';
import { buildWasm } from './build.mjs';
import { buildPackage } from './package.mjs';

const crate = path.join(repo, 'crate');
const testFiles = (dir) =>
  fs.existsSync(path.join(repo, dir))
    ? fs.readdirSync(path.join(repo, dir)).filter((f) => f.endsWith('.test.mjs')).map((f) => path.join(dir, f))
    : [];

const layers = [
  ['fmt', 'cargo fmt --check', () => run('cargo', ['fmt', '--all', '--check'])],
  // Natively every feature is on: `parallel` (rayon) is native only and
  // `render` compiles only for wasm32; without `parallel` the study code is
  // linted and tested in the wasm32 layers.
  ['clippy-native', 'clippy -D warnings, native, all targets', () =>
    run('cargo', ['clippy', '--workspace', '--all-targets', '--all-features', '--', '-D', 'warnings'])],
  ['clippy-wasm32', 'clippy -D warnings, wasm32, with and without the renderer', () => {
    const args = ['clippy', '--workspace', '--lib', '--tests', '--target', 'wasm32-unknown-unknown'];
    const lints = ['--', '-D', 'warnings'];
    return run('cargo', [...args, '--all-features', ...lints]) || run('cargo', [...args, ...lints]);
  }],
  ['cargo-test', 'native unit, integration and doc tests', () => run('cargo', ['test', '--workspace', '--all-features'])],
  ['batch', 'docs/batch/monte-carlo.slurm on a real Slurm (controller and node on localhost), merged = whole study', () => {
    if (run('cargo', ['build', '--workspace', '--all-features', '--bin', 'monte-carlo']) !== 0) return 1;
    return run('node', ['--test', ...testFiles('tests/batch')]);
  }],
  ['doc', 'cargo doc --no-deps with RUSTDOCFLAGS=-D warnings (broken links, missing docs)', () =>
    run('cargo', ['doc', '--workspace', '--no-deps'], { env: { RUSTDOCFLAGS: '-D warnings' } })],
  ['wasm-node', 'wasm-pack test --node: the numerics compiled to wasm', () =>
    // `--lib --test '*'` keeps doctests (native only) out of the wasm run.
    run('wasm-pack', ['test', '--node', '--mode', 'no-install', '--', '--lib', '--test', '*'], { cwd: crate })],
  ['js-contract', 'the JS API in Node against crate/pkg-node', () => {
    if (buildWasm('node') !== 0) return 1;
    return run('node', ['--test', ...testFiles('tests/node')]);
  }],
  ['fuzz', 'seeded hostile calls to every export and World method (FUZZ_SECONDS, default 40)', () => {
    if (buildWasm('node') !== 0) return 1;
    return run('node', ['--test', ...testFiles('tests/fuzz')]);
  }],
  ['package', 'npm pack; install into temp projects: tsc against the runtime, Node (ESM, CJS), Vite, webpack, esbuild, a plain page, the compat entries, the docs pages on the package alone in Chromium', () => {
    if (!buildPackage()) return 1;
    return run('node', ['--test', '--test-concurrency=1', ...testFiles('tests/package')]);
  }],
  ['browser', 'the pages in headless Chromium (WebGPU and WebGL2)', () => {
    // Both builds: the tests of the built site pack the npm package (scripts/site.mjs).
    if (buildWasm('web') !== 0 || buildWasm('node') !== 0) return 1;
    return run('node', ['--test', '--test-concurrency=1', ...testFiles('tests/browser')]);
  }],
];

const only = (() => {
  const i = process.argv.indexOf('--only');
  return i > 0 ? new Set(process.argv[i + 1].split(',')) : null;
})();

// A full run builds every target natively and for wasm32 once: incremental
// caches would only add about 1.3 GB of disk for nothing. A value the caller
// set is kept.
process.env.CARGO_INCREMENTAL ??= '0';

const t0 = performance.now();
const needBrowser = !only || only.has('browser') || only.has('package');
const needSlurm = !only || only.has('batch');
if (!ensureTools({ browser: needBrowser, slurm: needSlurm })) {
  console.error('npm test: the toolchain is incomplete (see above); no layer was run.');
  process.exit(1);
}
console.log(`tools: ready (${seconds(t0)} s)`);

const results = [];
for (const [name, what, fn] of layers) {
  if (only && !only.has(name)) continue;
  console.log(`\n=== ${name}: ${what}`);
  const t = performance.now();
  const status = fn();
  results.push({ name, what, ok: status === 0, time: seconds(t) });
}

console.log('\n=== summary');
for (const r of results) {
  console.log(`${r.ok ? 'PASS' : 'FAIL'}  ${r.name.padEnd(13)} ${r.time.padStart(6)} s  ${r.what}`);
}
const failed = results.filter((r) => !r.ok).length;
console.log(`layers: ${results.length - failed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);
