// `npm run bench -- --tables --against <dir>`: this checkout's kinematics
// step and control step against another checkout's, natively and in wasm
// under Node, in paired batches (bench-pairs.mjs: each set times one batch
// of this native, other native, this wasm and other wasm, a few
// milliseconds apart, the order rotating) so that a change's cost is
// measured under one machine load rather than read off two tables taken
// minutes apart.
//
// `<dir>` is another checkout whose Node package is built
// (`git worktree add /tmp/before <rev>`, then `node scripts/build.mjs node`
// there); its native batches run `cargo bench` in that checkout. Printed per
// workload: both checkouts' medians per step, natively and in wasm, and the
// median of the per-set ratios this/other (below 1: this checkout is
// faster).
//
//   npm run bench -- --tables --against /tmp/before [--pairs 21]
//   (pinned to one core; alone: node scripts/bench-step-ab.mjs <dir> [pairs])
import fs from 'node:fs';
import path from 'node:path';
import v8 from 'node:v8';
import { createRequire } from 'node:module';
import { spawnSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';
import { repo } from './lib.mjs';
import { WORKLOADS, median, nativeSide, pairedRatio, pairedSamples, wasmSide } from './bench-pairs.mjs';

export { median };

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

function loadPackage(root) {
  const file = path.join(root, 'crate', 'pkg-node', 'skeleton_avoidance.js');
  if (!fs.existsSync(file)) throw new Error(`--against: ${root} has no crate/pkg-node; run \`node scripts/build.mjs node\` there first`);
  return createRequire(import.meta.url)(file);
}

/** Prints the paired table of this checkout against `against`. */
export async function stepAbTable(against, pairs = 21) {
  const other = path.resolve(against);
  const packages = { this: loadPackage(repo), other: loadPackage(other) };
  console.log(`\n=== kinematics and control step, this checkout (${repo}) against ${other}`);
  console.log(`(${pairs} sets of paired batches; medians per step in µs; ratio = median of the per-set ratios this/other)`);
  const head = ['workload', 'native this', 'native other', 'ratio', 'wasm this', 'wasm other', 'ratio', 'wasm/native this'];
  console.log(`${head[0].padEnd(26)} ${head.slice(1).map((h) => h.padStart(12)).join(' ')}`);
  const us = (x) => (x / 1000).toFixed(x < 10_000 ? 3 : 1).padStart(12);
  const ratio = (a, b) => pairedRatio(a, b).toFixed(3).padStart(12);
  for (const [bench, workloads] of Object.entries(WORKLOADS)) {
    const sides = {
      'this/native': nativeSide(repo, bench),
      'other/native': nativeSide(other, bench),
      'this/wasm': wasmSide(packages.this),
      'other/wasm': wasmSide(packages.other),
    };
    try {
      for (const [id, s] of Object.entries(await pairedSamples(workloads, sides, pairs))) {
        console.log(`${id.padEnd(26)} ${us(median(s['this/native']))} ${us(median(s['other/native']))} ${ratio(s['this/native'], s['other/native'])} `
          + `${us(median(s['this/wasm']))} ${us(median(s['other/wasm']))} ${ratio(s['this/wasm'], s['other/wasm'])} ${ratio(s['this/wasm'], s['this/native'])}`);
      }
    } finally {
      for (const side of Object.values(sides)) side.close();
    }
  }
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  // TurboFan from the first call, as in scripts/bench.mjs.
  v8.setFlagsFromString('--no-liftoff');
  if (!process.argv[2]) {
    console.error('usage: node scripts/bench-step-ab.mjs <other checkout> [pairs]');
    process.exit(1);
  }
  await stepAbTable(process.argv[2], Number(process.argv[3] ?? 21));
}
