// Paired batches for the native/wasm tables of `npm run bench` and for
// `--tables --against`: the bench binaries serve batches on request
// (`SA_BATCH_SERVE=1`, crate/benches/common/serve.rs), and each native batch
// is timed back to back with the same batch in wasm under Node, the order
// alternating from pair to pair. A ratio is then the median of per-pair
// ratios of batches timed a few milliseconds apart.
//
// Why pairs: on this kind of shared machine the native kinematics step
// swung between 0.36 and 0.67 µs from one 100 ms stretch to the next within
// one process, so rounds a second apart (a native process, then the wasm
// rounds) compared different machines and the ratio moved by a third from
// run to run. The slow stretches come and go on either core, so `npm run
// bench` runs this file pinned to one core (`taskset`, scripts/bench.mjs):
// both sides then take turns on the same core, never at once. Unpinned, a
// native server and Node on different cores still read a dual-arm ratio of
// 0.95 in one run (1.57-1.61 in the others). Both sides still run the same workloads
// (`workloads::KinematicsStep`, the control-step worlds), the same batch
// sizes and the same untimed warm-up, and both keep their workload from
// batch to batch, so that pair k times the same steps of a scene on both.
//
//   node scripts/bench-pairs.mjs [--pairs N]   (the two tables alone, on the
//                                              Node package already built)
import os from 'node:os';
import path from 'node:path';
import readline from 'node:readline';
import v8 from 'node:v8';
import { createRequire } from 'node:module';
import { spawn, spawnSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';
import { repo, run } from './lib.mjs';

/** Steps of the control-step workloads' scripted scene before it rewinds. */
const CYCLE = 4000;

/**
 * The workloads: id, steps per batch, untimed warm-up steps. The control
 * step's warm-up is one cycle of its scene; the human row's batches are
 * whole cycles (its steps cost more while the human passes the arm).
 */
export const WORKLOADS = {
  kinematics: ['lwr4', 'panda', 'dual-arm'].map((name) => ({ id: `kinematics_step/${name}`, steps: 2000, warm: 4000 })),
  control_step: [
    ...[[10, 500], [100, 500], [1000, 100]].map(([n, steps]) => ({ id: `control_step/lwr4/${n}`, steps, warm: CYCLE })),
    { id: 'control_step/lwr4/human+10', steps: CYCLE, warm: CYCLE },
  ],
};

/** A batch of workload `id` in the Node package `sa`: `(steps) => checksum`. */
function wasmBatch(sa, id) {
  const [kind, arg, last] = id.split('/');
  if (kind === 'kinematics_step') return (n) => sa.benchKinematicsStep(arg, n);
  return last === 'human+10' ? (n) => sa.benchControlStep(n, 10, true) : (n) => sa.benchControlStep(n, Number(last));
}

/** A side that times batches in the Node package `sa`: `{ time(id, steps) → ns }`. */
export function wasmSide(sa) {
  return {
    async time(id, steps) {
      const run = wasmBatch(sa, id);
      const t0 = process.hrtime.bigint();
      run(steps);
      return Number(process.hrtime.bigint() - t0);
    },
    close() {},
  };
}

/**
 * A side that times batches in bench binary `bench` of the checkout at
 * `root`, built and started by cargo: `{ time(id, steps) → ns, close() }`.
 */
export function nativeSide(root, bench) {
  const child = spawn('cargo', ['bench', '-q', '-p', 'skeleton-avoidance', '--features', 'parallel', '--bench', bench], {
    cwd: root,
    env: { ...process.env, SA_BATCH_SERVE: '1' },
    stdio: ['pipe', 'pipe', 'inherit'],
  });
  const lines = readline.createInterface({ input: child.stdout })[Symbol.asyncIterator]();
  return {
    async time(id, steps) {
      child.stdin.write(`${id} ${steps}\n`);
      const { value, done } = await lines.next();
      if (done) throw new Error(`the native ${bench} bench in ${root} ended (exit ${child.exitCode})`);
      if (!/^\d+$/.test(value)) throw new Error(`the native ${bench} bench in ${root}: ${value}`);
      return Number(value);
    },
    close() {
      child.stdin.end();
    },
  };
}

/**
 * Times every workload of `workloads` on every side of `sides` (name →
 * side): an untimed warm-up on each, then `pairs` sets of one batch per
 * side, the sides' order rotating from set to set. Returns
 * `{ id: { side: [ns per step, one per set] } }`, set k aligned across sides.
 */
export async function pairedSamples(workloads, sides, pairs) {
  const names = Object.keys(sides);
  const samples = {};
  for (const w of workloads) {
    for (const name of names) await sides[name].time(w.id, w.warm);
    const per = Object.fromEntries(names.map((name) => [name, []]));
    for (let k = 0; k < pairs; k++) {
      for (let j = 0; j < names.length; j++) {
        const name = names[(j + k) % names.length];
        per[name].push((await sides[name].time(w.id, w.steps)) / w.steps);
      }
    }
    samples[w.id] = per;
  }
  return samples;
}

export const median = (xs) => xs.slice().sort((a, b) => a - b)[Math.floor(xs.length / 2)];

/** The median of the per-set ratios `a[k] / b[k]`. */
export const pairedRatio = (a, b) => median(a.map((x, k) => x / b[k]));

/**
 * Times bench `bench`'s workloads in paired batches, native and wasm back to
 * back (`pairs` pairs each); prints one table with medians and the median
 * per-pair ratio.
 */
async function table(sa, title, bench, goals, pairs) {
  const sides = { native: nativeSide(repo, bench), wasm: wasmSide(sa) };
  let samples;
  try {
    samples = await pairedSamples(WORKLOADS[bench], sides, pairs);
  } finally {
    for (const side of Object.values(sides)) side.close();
  }
  console.log(`\n=== ${title}`);
  console.log(`(${pairs} pairs of batches on one core, native and wasm timed back to back, the order alternating; medians per step; ratio = median of the per-pair ratios)`);
  console.log(`${'workload'.padEnd(26)} ${'native µs'.padStart(10)} ${'wasm µs'.padStart(10)} ${'wasm/native'.padStart(12)}  goal`);
  for (const [id, { native, wasm }] of Object.entries(samples)) {
    const us = (x) => (x / 1000).toFixed(x < 10_000 ? 3 : 1).padStart(10);
    console.log(`${id.padEnd(26)} ${us(median(native))} ${us(median(wasm))} ${pairedRatio(wasm, native).toFixed(2).padStart(12)}  ${goals[id] ?? ''}`);
  }
}

/** The kinematics-step and control-step tables of `npm run bench`. */
async function tables(sa, pairs) {
  await table(
    sa,
    'FK + skeleton + 8 control-point Jacobians (J_θ, J_a, J_d)',
    'kinematics',
    { 'kinematics_step/lwr4': 'native ≤ 2 µs, wasm/native ≤ 1.5' },
    pairs ?? 41,
  );
  await table(
    sa,
    'full control step: lwr4 among N spheres (FK, skeleton, scene query, control points, transitions, Jacobians, controller)',
    'control_step',
    {
      'control_step/lwr4/10': 'native ≤ 10 µs, wasm/native ≤ 1.5',
      'control_step/lwr4/100': 'native ≤ 50 µs, wasm/native ≤ 1.5',
      'control_step/lwr4/1000': 'native ≤ 330 µs, wasm/native ≤ 1.5',
    },
    pairs ?? 31,
  );
}

/**
 * Runs `node <args>` pinned to the machine's last core when `taskset` is
 * there (both sides of every pair then run on that core); returns its exit
 * status.
 */
export function runPinned(args) {
  const node = [process.execPath, ...args];
  if (spawnSync('taskset', ['--version']).status !== 0) {
    console.log('(taskset not found: the paired batches run unpinned)');
    return run(node[0], node.slice(1));
  }
  return run('taskset', ['-c', String(os.availableParallelism() - 1), ...node]);
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  // TurboFan from the first call, as in scripts/bench.mjs.
  v8.setFlagsFromString('--no-liftoff');
  const sa = createRequire(import.meta.url)(path.join(repo, 'crate', 'pkg-node', 'skeleton_avoidance.js'));
  const i = process.argv.indexOf('--pairs');
  await tables(sa, i > 0 ? Number(process.argv[i + 1]) : undefined);
}
