// `npm run bench -- --frames --against <dir>`: this checkout's playground
// against another build, interleaved, so that a change's effect on the frame
// rate is measured in one run rather than read off two tables taken minutes
// apart (on a shared machine those differ by more than most changes).
//
// `<dir>` is another checkout with its wasm package built (its web/ and
// crate/pkg are served: `git worktree add /tmp/before <rev>`, then
// `node scripts/build.mjs web` there), or a wasm package folder alone (served
// with this checkout's web/). Per example and round, each build gets a fresh
// browser and one window on WebGPU; the order of the two alternates from
// round to round. Printed per example: both builds' medians (fps, GPU and
// CPU ms per frame) and the median of the paired differences, with how many
// rounds this build won. With `--drag`, the view is dragged a pixel to and
// fro every frame (bench-frames.mjs), so that every frame draws: the way to
// compare the cost of drawing where an example settles (a frame whose
// picture is the one on screen is not drawn again).
//
//   npm run bench -- --frames --against /tmp/before [--only human-panda,chattering] [--rounds 4] [--drag]
import fs from 'node:fs';
import path from 'node:path';
import { serve } from './serve.mjs';
import { buildWasm } from './build.mjs';
import { WINDOW_MS, frameRows, measure } from './bench-frames.mjs';

const median = (xs) => xs.slice().sort((a, b) => a - b)[Math.floor(xs.length / 2)];

/** What `--against` names: `{ tree }` (a checkout) or `{ pkg }` (a wasm package); throws otherwise. */
export function againstSource(dir) {
  const abs = path.resolve(dir);
  if (fs.existsSync(path.join(abs, 'web', 'index.html'))) {
    if (!fs.existsSync(path.join(abs, 'crate', 'pkg', 'skeleton_avoidance_bg.wasm'))) {
      throw new Error(`--against ${dir}: a checkout without its wasm package; run \`node scripts/build.mjs web\` there first`);
    }
    return { tree: abs };
  }
  if (fs.existsSync(path.join(abs, 'skeleton_avoidance_bg.wasm'))) return { pkg: abs };
  throw new Error(`--against ${dir}: neither a checkout (web/index.html and crate/pkg) nor a wasm package (skeleton_avoidance_bg.wasm)`);
}

/** One window of `row` on WebGPU in a fresh browser serving `source` (the view dragged with `drag`). */
async function oneWindow(source, row, drag) {
  const { launch } = await import('../tests/browser/chromium.mjs');
  const { server, url } = await serve({ port: 0, ...source });
  const browser = await launch({ webgpu: true, viewport: { width: 1280, height: 800 } });
  try {
    const page = await browser.context.newPage();
    const m = await measure(page, browser.profile, url, row.example, 'webgpu', { files: row.files, windows: 1, drag });
    return drag ? m.dragged : m;
  } finally {
    await browser.close();
    server.close();
  }
}

/** Prints the A/B table; returns false when a build could not be made or measured. */
export async function abTable(examples, { against, only = null, rounds = 4, drag = false }) {
  let other;
  try {
    other = againstSource(against);
  } catch (e) {
    console.error(e.message);
    return false;
  }
  if (!Number.isInteger(rounds) || rounds < 1) {
    console.error(`--rounds: expected a whole number ≥ 1, got ${rounds}`);
    return false;
  }
  if (buildWasm('web') !== 0) return false;
  const sources = { this: {}, other };
  console.log(`\n=== frame rate, this checkout (A) against ${path.resolve(against)} (B): WebGPU, 1280×800, running${drag ? ', the view dragged' : ''},`);
  console.log(`    ${rounds} rounds, a fresh browser and one ${WINDOW_MS / 1000} s window per build and round, the order alternating`);
  const head = ['example'.padEnd(20), 'A fps'.padStart(6), 'B fps'.padStart(6), 'A−B'.padStart(6), 'A won'.padStart(6),
    'A GPU'.padStart(6), 'B GPU'.padStart(6), 'A CPU'.padStart(6), 'B CPU'.padStart(6)];
  console.log(`${head.join(' ')}   (medians; GPU, CPU: ms per frame of the GPU process, of all the browser's processes)`);
  for (const row of frameRows(examples, only)) {
    const a = [];
    const b = [];
    for (let r = 0; r < rounds; r++) {
      const order = r % 2 === 0 ? ['this', 'other'] : ['other', 'this'];
      for (const which of order) (which === 'this' ? a : b).push(await oneWindow(sources[which], row, drag));
    }
    const diffs = a.map((m, k) => m.fps - b[k].fps);
    const med = (ms, key) => median(ms.map((m) => m[key])).toFixed(1).padStart(6);
    const cells = [row.name.padEnd(20), med(a, 'fps'), med(b, 'fps'), median(diffs).toFixed(1).padStart(6),
      `${diffs.filter((d) => d > 0).length}/${rounds}`.padStart(6), med(a, 'gpuMs'), med(b, 'gpuMs'), med(a, 'cpuMs'), med(b, 'cpuMs')];
    console.log(cells.join(' '));
  }
  return true;
}
