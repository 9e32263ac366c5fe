// `npm run bench`: the criterion benchmarks natively, then the same workloads
// compiled to wasm and timed in Node, printed as one table with ratios
// measured in this run. Machines are shared and noisy: medians, not means.
import fs from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';
import { repo, run } from './lib.mjs';
import { ensureTools } from './tools.mjs';
import { buildWasm } from './build.mjs';

const benches = fs
  .readdirSync(path.join(repo, 'crate', 'benches'))
  .filter((f) => f.endsWith('.rs'))
  .map((f) => f.slice(0, -3));

if (!ensureTools()) process.exit(1);
for (const b of benches) {
  console.log(`\n=== cargo bench --bench ${b}`);
  if (run('cargo', ['bench', '-p', 'skeleton-avoidance', '--bench', b]) !== 0) process.exit(1);
}
if (buildWasm('node') !== 0) process.exit(1);

const require = createRequire(import.meta.url);
const sa = require(path.join(repo, 'crate', 'pkg-node', 'skeleton_avoidance.js'));

/** Median criterion estimate (ns) of a benchmark id such as "kinematics_step/lwr4". */
function nativeMedian(id) {
  const file = path.join(repo, 'target', 'criterion', ...id.split('/'), 'new', 'estimates.json');
  return JSON.parse(fs.readFileSync(file, 'utf8')).median.point_estimate;
}

/** Median ns per iteration of `fn(batch)` over `samples` timed batches. */
function wasmMedian(fn, { batch = 2000, samples = 41 } = {}) {
  fn(batch); // warm-up (compilation tiers)
  fn(batch);
  const per = [];
  for (let s = 0; s < samples; s++) {
    const t0 = process.hrtime.bigint();
    fn(batch);
    per.push(Number(process.hrtime.bigint() - t0) / batch);
  }
  per.sort((a, b) => a - b);
  return per[Math.floor(per.length / 2)];
}

const rows = [];
for (const name of ['lwr4', 'panda', 'dual-arm']) {
  const id = `kinematics_step/${name}`;
  const native = nativeMedian(id);
  const wasm = wasmMedian((n) => sa.benchKinematicsStep(name, n));
  rows.push({ id, native, wasm, goal: name === 'lwr4' ? 'native ≤ 2000 ns, wasm/native ≤ 1.5' : '' });
}

console.log('\n=== FK + skeleton + 8 control-point Jacobians (J_θ, J_a, J_d), median per step');
console.log(`${'workload'.padEnd(26)} ${'native ns'.padStart(10)} ${'wasm ns'.padStart(10)} ${'wasm/native'.padStart(12)}  goal`);
for (const r of rows) {
  console.log(`${r.id.padEnd(26)} ${r.native.toFixed(0).padStart(10)} ${r.wasm.toFixed(0).padStart(10)} ${(r.wasm / r.native).toFixed(2).padStart(12)}  ${r.goal}`);
}

// One full control step of lwr4 among N static spheres (issue 5): FK,
// skeleton, scene query, control points, transitions, Jacobians, controller.
const stepRows = [];
for (const [n, goal, batch] of [[10, 10e3, 2000], [100, 50e3, 1000], [1000, 330e3, 200]]) {
  const id = `control_step/lwr4/${n}`;
  const native = nativeMedian(id);
  const wasm = wasmMedian((k) => sa.benchControlStep(k, n), { batch, samples: 21 });
  stepRows.push({ id, native, wasm, goal: `native ≤ ${(goal / 1000).toFixed(0)} µs, wasm/native ≤ 1.5` });
}
console.log('\n=== full control step (lwr4, N obstacles, 1 kHz), median per step');
console.log(`${'workload'.padEnd(26)} ${'native ns'.padStart(10)} ${'wasm ns'.padStart(10)} ${'wasm/native'.padStart(12)}  goal`);
for (const r of stepRows) {
  console.log(`${r.id.padEnd(26)} ${r.native.toFixed(0).padStart(10)} ${r.wasm.toFixed(0).padStart(10)} ${(r.wasm / r.native).toFixed(2).padStart(12)}  ${r.goal}`);
}
