// `npm run bench`: the criterion benchmarks natively (their own reports),
// then, for the workloads with a native/wasm goal, tables of paired batches:
// each native batch (a bench binary serving batches) timed back to back with
// the same batch in wasm under Node (bench-pairs.mjs), so that both see the
// same machine load and the ratios are measured in this run. Machines are
// shared and noisy: medians, not means.
//
// Last, the playground's frame rate in headless Chromium (bench-frames.mjs).
//
//   npm run bench [-- --tables]   (--tables skips the criterion runs;
//                                  --tables --against <dir> measures this
//                                  kinematics and control steps against
//                                  another checkout's in paired
//                                  batches: bench-step-ab.mjs; --pairs N)
//   npm run bench -- --frames     (only the frame-rate table; --only a,b
//                                  measures those rows; --against <dir>
//                                  measures this build against another,
//                                  interleaved: bench-ab.mjs; --drag
//                                  drags the view so every frame draws)
//   npm run bench -- --camera     (only the playground with its camera on:
//                                  fps and the estimator's Hz; bench-camera.mjs)
//   npm run bench -- --reach      (only the reach benchmark: NEO's 198 PR2
//                                  problems on the arm's fitted volumes,
//                                  100 random Panda problems and
//                                  MotionBenchMaker's 700, each run by the
//                                  constraints, the repulsion, NEO as
//                                  published and NEO through the limiter:
//                                  `cargo run --release --example reach`;
//                                  `--only pr2,panda,mbm` and
//                                  `--controllers neo,...` pass through)
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import v8 from 'node:v8';
import { createRequire } from 'node:module';
import { repo, run } from './lib.mjs';
import { ensureTools } from './tools.mjs';
import { buildWasm } from './build.mjs';
import { frameRows, frameTable } from './bench-frames.mjs';
import { cameraTable } from './bench-camera.mjs';
import { abTable } from './bench-ab.mjs';
import { median, nativeRound as nativeRoundIn } from './bench-step-ab.mjs';
import { runPinned } from './bench-pairs.mjs';

// The wasm batches time V8's optimising tier (TurboFan), as the native ones
// time optimised code: by default V8 first runs Liftoff's baseline code and
// tiers a function up only after a budget of work, in the background; on a
// loaded machine that took seconds (the 10-sphere control step ran at 90 µs
// per step before it reached 12 µs), so rounds timed Liftoff code and the
// ratios scattered (2.1-3.4 on that row in three runs). Without Liftoff,
// every function is compiled by TurboFan on its first call.
v8.setFlagsFromString('--no-liftoff');

const benches = fs
  .readdirSync(path.join(repo, 'crate', 'benches'))
  .filter((f) => f.endsWith('.rs'))
  .map((f) => f.slice(0, -3));

// --tables: only the native/wasm tables, without the full criterion runs.
const quick = process.argv.includes('--tables');
if (!ensureTools({ browser: true })) process.exit(1);
if (process.argv.includes('--reach')) {
  console.log('\n=== reach benchmark (crate/examples/reach.rs; every controller, one evaluator: strict = within 1 cm and 2° in 10 s, within every limit, no contact beginning while moving; NEO\'s count = summed pose error < 0.25 m + rad within 25 s)');
  const pass = ['only', 'controllers'].flatMap((name) => (option(name) ? [`--${name}`, option(name)] : []));
  process.exit(run('cargo', ['run', '--release', '-q', '-p', 'skeleton-avoidance', '--example', 'reach', '--', ...pass]));
}
if (process.argv.includes('--camera')) process.exit((await cameraTable()) ? 0 : 1);
if (process.argv.includes('--frames')) {
  const only = option('only')?.split(',');
  const unknown = only?.filter((name) => !frameRows(exampleNames()).some((r) => r.name === name));
  if (unknown?.length) {
    console.error(`--only: no frame row named ${unknown.join(', ')} (rows: ${frameRows(exampleNames()).map((r) => r.name).join(', ')})`);
    process.exit(1);
  }
  const against = option('against');
  const ok = against
    ? await abTable(exampleNames(), { against, only, rounds: Number(option('rounds') ?? 4), drag: process.argv.includes('--drag') })
    : await frameTable(exampleNames(), only);
  process.exit(ok ? 0 : 1);
}
if (quick && option('against')) {
  if (buildWasm('node') !== 0) process.exit(1);
  process.exit(runPinned([path.join(repo, 'scripts', 'bench-step-ab.mjs'), option('against'), option('pairs') ?? '21']));
}
for (const b of quick ? [] : benches) {
  console.log(`\n=== cargo bench --bench ${b}`);
  if (run('cargo', ['bench', '-p', 'skeleton-avoidance', '--features', 'parallel', '--bench', b]) !== 0) process.exit(1);
}
if (buildWasm('node') !== 0) process.exit(1);

/** The value after `--name` on the command line, if any. */
function option(name) {
  const i = process.argv.indexOf(`--${name}`);
  return i > 0 ? process.argv[i + 1] : undefined;
}

/** The shipped examples, in the crate's order (scenarios/*.json). */
function exampleNames() {
  const list = fs.readFileSync(path.join(repo, 'crate', 'src', 'scenario', 'examples.rs'), 'utf8');
  const names = list.match(/EXAMPLE_NAMES[^=]*=\s*\[([^\]]*)\]/)?.[1].match(/"[^"]+"/g) ?? [];
  return names.map((n) => n.slice(1, -1));
}

const require = createRequire(import.meta.url);
const sa = require(path.join(repo, 'crate', 'pkg-node', 'skeleton_avoidance.js'));

const nativeRound = (bench) => nativeRoundIn(repo, bench);

// The kinematics-step and control-step tables (bench-pairs.mjs), pinned to
// one core.
if (runPinned([path.join(repo, 'scripts', 'bench-pairs.mjs')]) !== 0) process.exit(1);

// Dynamics per control step on the 7-DOF presets with inertial data:
// Newton–Euler inverse dynamics and the mass matrix, natively (medians of
// the batch rounds of crate/benches/dynamics.rs).
{
  const rounds = 5;
  const samples = {};
  for (let k = 0; k < rounds; k++) {
    for (const [id, ns] of Object.entries(nativeRound('dynamics'))) (samples[id] ??= []).push(ns);
  }
  const goals = { rnea: 'native ≤ 2 µs', mass_matrix: 'native ≤ 3 µs' };
  console.log('\n=== dynamics per control step: RNEA τ = M q̈ + C q̇ + g and the mass matrix M(q), 7-DOF presets');
  console.log(`(${rounds} native rounds; medians per call, reused workspace)`);
  console.log(`${'workload'.padEnd(30)} ${'native µs'.padStart(10)}  goal`);
  for (const [id, xs] of Object.entries(samples)) {
    console.log(`${id.padEnd(30)} ${(median(xs) / 1000).toFixed(3).padStart(10)}  ${goals[id.split('/')[1]] ?? ''}`);
  }
}

// Monte Carlo throughput: runs per second of a 2 s scenario (lwr4 at 1 kHz,
// noisy sensing), natively on one thread and on every core (rayon), and in
// wasm under Node (one thread: a wasm module has no threads here).
{
  const rounds = 3;
  const native = {};
  const wasm = [];
  for (let k = 0; k < rounds; k++) {
    for (const [id, ns] of Object.entries(nativeRound('monte_carlo'))) (native[id] ??= []).push(ns);
    const runs = 4;
    sa.benchMonteCarlo(1); // warm-up
    const t0 = process.hrtime.bigint();
    sa.benchMonteCarlo(runs);
    wasm.push(Number(process.hrtime.bigint() - t0) / runs);
  }
  const perSecond = (ns) => (1e9 / ns).toFixed(1).padStart(10);
  console.log('\n=== Monte Carlo: runs per second of a 2 s scenario (lwr4, 1 kHz, noisy sensing)');
  console.log(`(${rounds} alternating native/wasm rounds; medians; ${os.availableParallelism()} cores on this machine)`);
  console.log(`${'study'.padEnd(26)} ${'runs/s'.padStart(10)} ${'vs 1 thread'.padStart(12)}`);
  const one = median(native['monte_carlo/1-thread'] ?? [NaN]);
  for (const [id, xs] of [...Object.entries(native), ['monte_carlo/wasm (Node)', wasm]]) {
    console.log(`${id.padEnd(26)} ${perSecond(median(xs))} ${(one / median(xs)).toFixed(2).padStart(12)}`);
  }
}

if (!(await frameTable(exampleNames()))) process.exit(1);
if (!(await cameraTable())) process.exit(1);
