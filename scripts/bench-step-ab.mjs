// `npm run bench -- --tables --against <dir>`: this checkout's control step
// against another checkout's, natively and in wasm under Node, rounds
// interleaved (this native, other native, this wasm, other wasm; the order of
// the two checkouts alternating from round to round) so that a change's cost
// is measured under one machine load rather than read off two tables taken
// minutes apart.
//
// `<dir>` is another checkout whose Node package is built
// (`git worktree add /tmp/before <rev>`, then `node scripts/build.mjs node`
// there); its native rounds run `cargo bench` in that checkout. Printed per
// workload: both checkouts' medians per step, natively and in wasm, and the
// median of the per-round ratios this/other (below 1: this checkout is
// faster).
//
//   npm run bench -- --tables --against /tmp/before [--rounds 5]
import fs from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';
import { spawnSync } from 'node:child_process';
import { repo } from './lib.mjs';

export const median = (xs) => xs.slice().sort((a, b) => a - b)[Math.floor(xs.length / 2)];

/** One native round of bench `bench` in checkout `root`: `{ id: ns per step }`. */
export function nativeRound(root, bench) {
  const r = spawnSync('cargo', ['bench', '-q', '-p', 'skeleton-avoidance', '--features', 'parallel', '--bench', bench], {
    cwd: root,
    encoding: 'utf8',
    env: { ...process.env, SA_BATCH_ROUND: '1' },
  });
  if (r.status !== 0) throw new Error(`native round of ${bench} in ${root} failed: ${r.stderr}`);
  return Object.fromEntries(
    r.stdout.split('\n').filter((l) => /^\S+ [0-9.]+$/.test(l.trim())).map((l) => {
      const [id, ns] = l.trim().split(/\s+/);
      return [id, Number(ns)];
    }),
  );
}

/**
 * Median ns per step of `fn(batch)` over `samples` timed batches, after an
 * untimed warm-up of `warmUp` steps (`fn(warmUp)`), the same as the native
 * rounds' (crate/benches).
 */
export function wasmMedian(fn, batch, samples, warmUp = batch) {
  fn(warmUp);
  const per = [];
  for (let s = 0; s < samples; s++) {
    const t0 = process.hrtime.bigint();
    fn(batch);
    per.push(Number(process.hrtime.bigint() - t0) / batch);
  }
  return median(per);
}

/**
 * Steps of the control-step workloads' scripted scene before they rewind it
 * (4 s at 1 kHz). Each workload first runs one such cycle untimed, as the
 * native rounds do (crate/benches/control_step.rs), so that both sides time
 * the same steps of the scene (a step's cost varies along it: the human
 * passes close to the arm twice per cycle) and V8 has compiled every path
 * the scene reaches before the timing starts.
 */
const CYCLE = 4000;

/** The control-step workloads of `npm run bench` in the Node package `sa`. */
export function wasmControlStep(sa) {
  return Object.fromEntries([
    ...[[10, 500], [100, 500], [1000, 100]].map(([n, batch]) =>
      [`control_step/lwr4/${n}`, wasmMedian((k) => sa.benchControlStep(k, n), batch, 9, CYCLE)]),
    // Whole cycles: the human's passes make a half-second batch's cost
    // bimodal, and a median of such batches fell on either mode.
    ['control_step/lwr4/human+10', wasmMedian((k) => sa.benchControlStep(k, 10, true), CYCLE, 9, CYCLE)],
  ]);
}

function loadPackage(root) {
  const file = path.join(root, 'crate', 'pkg-node', 'skeleton_avoidance.js');
  if (!fs.existsSync(file)) throw new Error(`--against: ${root} has no crate/pkg-node; run \`node scripts/build.mjs node\` there first`);
  return createRequire(import.meta.url)(file);
}

/** Prints the interleaved table of this checkout against `against`. */
export function stepAbTable(against, rounds = 5) {
  const other = path.resolve(against);
  const builds = { this: { root: repo, sa: loadPackage(repo) }, other: { root: other, sa: loadPackage(other) } };
  const samples = {};
  const add = (build, kind, values) => {
    for (const [id, ns] of Object.entries(values)) ((samples[id] ??= {})[`${build}/${kind}`] ??= []).push(ns);
  };
  for (let k = 0; k < rounds; k++) {
    const order = k % 2 === 0 ? ['this', 'other'] : ['other', 'this'];
    for (const b of order) add(b, 'native', nativeRound(builds[b].root, 'control_step'));
    for (const b of order) add(b, 'wasm', wasmControlStep(builds[b].sa));
  }
  console.log(`\n=== control step, this checkout (${repo}) against ${other}`);
  console.log(`(${rounds} interleaved rounds; medians per step in µs; ratio = median of the per-round ratios this/other)`);
  const head = ['workload', 'native this', 'native other', 'ratio', 'wasm this', 'wasm other', 'ratio', 'wasm/native this'];
  console.log(`${head[0].padEnd(26)} ${head.slice(1).map((h) => h.padStart(12)).join(' ')}`);
  const us = (x) => (x / 1000).toFixed(x < 10_000 ? 3 : 1).padStart(12);
  const ratio = (a, b) => median(a.map((x, k) => x / b[k])).toFixed(3).padStart(12);
  for (const [id, s] of Object.entries(samples)) {
    if (!s['this/wasm'] || !s['other/wasm']) continue;
    console.log(`${id.padEnd(26)} ${us(median(s['this/native']))} ${us(median(s['other/native']))} ${ratio(s['this/native'], s['other/native'])} `
      + `${us(median(s['this/wasm']))} ${us(median(s['other/wasm']))} ${ratio(s['this/wasm'], s['other/wasm'])} ${ratio(s['this/wasm'], s['this/native'])}`);
  }
}
