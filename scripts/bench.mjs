// `npm run bench`: the criterion benchmarks natively, then the same workloads
// compiled to wasm and timed in Node, printed as one table with ratios
// measured in this run. Machines are shared and noisy: medians, not means.
import fs from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';
import { spawnSync } from 'node:child_process';
import { repo, run } from './lib.mjs';
import { ensureTools } from './tools.mjs';
import { buildWasm } from './build.mjs';

const benches = fs
  .readdirSync(path.join(repo, 'crate', 'benches'))
  .filter((f) => f.endsWith('.rs'))
  .map((f) => f.slice(0, -3));

const quick = process.argv.includes('--wasm-only'); // reuse the last native run
if (!ensureTools()) process.exit(1);
for (const b of quick ? [] : benches) {
  console.log(`\n=== cargo bench --bench ${b}`);
  if (run('cargo', ['bench', '-p', 'skeleton-avoidance', '--bench', b]) !== 0) process.exit(1);
}
if (buildWasm('node') !== 0) process.exit(1);

const require = createRequire(import.meta.url);
const sa = require(path.join(repo, 'crate', 'pkg-node', 'skeleton_avoidance.js'));

/** One native round: the bench binary's batch mode, `{ id: ns }`. */
function nativeRound() {
  const r = spawnSync('cargo', ['bench', '-q', '-p', 'skeleton-avoidance', '--bench', 'kinematics'], {
    cwd: repo,
    encoding: 'utf8',
    env: { ...process.env, SA_BATCH_ROUND: '1' },
  });
  if (r.status !== 0) throw new Error(`native round failed: ${r.stderr}`);
  return Object.fromEntries(
    r.stdout.split('\n').filter((l) => l.startsWith('kinematics_step/')).map((l) => {
      const [id, ns] = l.trim().split(/\s+/);
      return [id, Number(ns)];
    }),
  );
}

/** One wasm round: the same batches inside wasm, timed from Node. */
function wasmRound() {
  const out = {};
  for (const name of ['lwr4', 'panda', 'dual-arm']) {
    const batch = 2000;
    sa.benchKinematicsStep(name, 2 * batch); // warm-up (compilation tiers)
    const per = [];
    for (let s = 0; s < 15; s++) {
      const t0 = process.hrtime.bigint();
      sa.benchKinematicsStep(name, batch);
      per.push(Number(process.hrtime.bigint() - t0) / batch);
    }
    per.sort((a, b) => a - b);
    out[`kinematics_step/${name}`] = per[Math.floor(per.length / 2)];
  }
  return out;
}

const median = (xs) => xs.slice().sort((a, b) => a - b)[Math.floor(xs.length / 2)];

// Alternate native and wasm rounds so that both see the same machine load.
const rounds = { native: {}, wasm: {} };
for (let k = 0; k < 7; k++) {
  for (const [kind, fn] of [['native', nativeRound], ['wasm', wasmRound]]) {
    for (const [id, ns] of Object.entries(fn())) (rounds[kind][id] ??= []).push(ns);
  }
}
const rows = Object.keys(rounds.native).map((id) => ({
  id,
  native: median(rounds.native[id]),
  wasm: median(rounds.wasm[id]),
  ratios: rounds.native[id].map((n, k) => rounds.wasm[id][k] / n),
  goal: id.endsWith('/lwr4') ? 'native ≤ 2000 ns, wasm/native ≤ 1.5' : '',
}));

console.log('\n=== FK + skeleton + 8 control-point Jacobians (J_θ, J_a, J_d), median per step');
console.log('(7 alternating native/wasm rounds of 15 batches × 2000 steps; medians; ratio = median of per-round ratios)');
console.log(`${'workload'.padEnd(26)} ${'native ns'.padStart(10)} ${'wasm ns'.padStart(10)} ${'wasm/native'.padStart(12)}  goal`);
for (const r of rows) {
  console.log(`${r.id.padEnd(26)} ${r.native.toFixed(0).padStart(10)} ${r.wasm.toFixed(0).padStart(10)} ${median(r.ratios).toFixed(2).padStart(12)}  ${r.goal}`);
}

// One full control step of lwr4 among N static spheres (issue 5): FK,
// skeleton, scene query, control points, transitions, Jacobians, controller.
// Native: criterion's median from the `control_step` bench run above; wasm:
// the same workload (`benchControlStep`) timed from Node in this run.
function criterionMedian(id) {
  const file = path.join(repo, 'target', 'criterion', id.replaceAll('/', '_'), 'new', 'estimates.json');
  return JSON.parse(fs.readFileSync(file, 'utf8')).median.point_estimate;
}
const stepRows = [];
for (const [n, goal, batch] of [[10, 10, 2000], [100, 50, 500], [1000, 330, 100]]) {
  const id = `control_step/lwr4/${n}`;
  sa.benchControlStep(batch, n); // warm-up (compilation tiers)
  const per = [];
  for (let s = 0; s < 15; s++) {
    const t0 = process.hrtime.bigint();
    sa.benchControlStep(batch, n);
    per.push(Number(process.hrtime.bigint() - t0) / batch);
  }
  stepRows.push({ id, native: criterionMedian(id), wasm: median(per), goal: `native ≤ ${goal} µs, wasm/native ≤ 1.5` });
}
console.log('\n=== full control step (lwr4 among N spheres, 1 kHz), median per step');
console.log(`${'workload'.padEnd(26)} ${'native ns'.padStart(10)} ${'wasm ns'.padStart(10)} ${'wasm/native'.padStart(12)}  goal`);
for (const r of stepRows) {
  console.log(`${r.id.padEnd(26)} ${r.native.toFixed(0).padStart(10)} ${r.wasm.toFixed(0).padStart(10)} ${(r.wasm / r.native).toFixed(2).padStart(12)}  ${r.goal}`);
}
