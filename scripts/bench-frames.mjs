// The playground's frame rate in headless Chromium, for `npm run bench`:
// every example on WebGPU and on WebGL2 (both software-rendered here, by
// SwiftShader), 1280×800, running. Per example and backend: the median over
// a few windows of the frames per second, the 90th percentile of the frame
// interval, the CPU time Chromium's GPU process spent per frame (Linux
// only: read from /proc) and the triangles drawn. A frame rate depends on
// the machine: this is a measurement with a goal beside it, not a test.
import fs from 'node:fs';
import { serve } from './serve.mjs';
import { buildWasm } from './build.mjs';

const WINDOW_MS = 3000;
const WINDOWS = 3;

/** CPU seconds of Chromium's GPU process so far (null off Linux). */
function gpuProcessSeconds() {
  if (!fs.existsSync('/proc/self/stat')) return null;
  let total = 0;
  for (const pid of fs.readdirSync('/proc').filter((p) => /^\d+$/.test(p))) {
    try {
      if (!fs.readFileSync(`/proc/${pid}/cmdline`, 'utf8').includes('--type=gpu-process')) continue;
      // utime and stime: fields 14 and 15, counted after the command name.
      const fields = fs.readFileSync(`/proc/${pid}/stat`, 'utf8').split(') ')[1].split(' ');
      total += (Number(fields[11]) + Number(fields[12])) / 100;
    } catch {
      // The process ended between the listing and the read.
    }
  }
  return total;
}

/** rAF timestamps of `page` over `ms` milliseconds. */
const timestamps = (page, ms) => page.evaluate((ms) => new Promise((resolve) => {
  const ts = [];
  const tick = (t) => {
    ts.push(t);
    if (t - ts[0] < ms) requestAnimationFrame(tick);
    else resolve(ts);
  };
  requestAnimationFrame(tick);
}), ms);

const median = (xs) => xs.slice().sort((a, b) => a - b)[Math.floor(xs.length / 2)];

/** One example on one backend: `{ fps, p90, gpuMs, triangles }` (medians over the windows). */
async function measure(page, url, name, backend) {
  await page.goto(`${url}?scenario=${name}&backend=${backend}`);
  await page.evaluate(() => window.playground.ready);
  await page.waitForTimeout(1000);
  const fps = [];
  const p90 = [];
  const gpuMs = [];
  for (let w = 0; w < WINDOWS; w++) {
    const cpu0 = gpuProcessSeconds();
    const ts = await timestamps(page, WINDOW_MS);
    const cpu1 = gpuProcessSeconds();
    const gaps = ts.slice(1).map((t, k) => t - ts[k]).sort((a, b) => a - b);
    fps.push(gaps.length / ((ts.at(-1) - ts[0]) / 1000));
    p90.push(gaps[Math.floor(0.9 * gaps.length)]);
    if (cpu0 !== null) gpuMs.push((1000 * (cpu1 - cpu0)) / gaps.length);
  }
  const triangles = await page.evaluate(() => window.playground.state().triangles);
  return { fps: median(fps), p90: median(p90), gpuMs: gpuMs.length ? median(gpuMs) : NaN, triangles };
}

/** Prints the frame-rate table; returns false when the page could not be measured. */
export async function frameTable(examples) {
  if (buildWasm('web') !== 0) return false;
  const { launch } = await import('../tests/browser/chromium.mjs');
  const { server, url } = await serve({ port: 0 });
  const browser = await launch({ webgpu: true, viewport: { width: 1280, height: 800 } });
  try {
    const page = await browser.context.newPage();
    console.log('\n=== playground frame rate: headless Chromium, software rendering (SwiftShader), 1280×800, running');
    console.log(`(median of ${WINDOWS} windows of ${WINDOW_MS / 1000} s; GPU ms = CPU time of Chromium's GPU process per frame, on two cores)`);
    console.log(`${'example'.padEnd(20)} ${'backend'.padEnd(8)} ${'fps'.padStart(6)} ${'p90 ms'.padStart(7)} ${'GPU ms'.padStart(7)} ${'triangles'.padStart(10)}  goal`);
    for (const name of examples) {
      for (const backend of ['webgpu', 'webgl2']) {
        const m = await measure(page, url, name, backend);
        const goal = backend === 'webgpu' ? `≥ 50 fps ${m.fps >= 50 ? '(met)' : '(NOT met)'}` : '(reported)';
        console.log(`${name.padEnd(20)} ${backend.padEnd(8)} ${m.fps.toFixed(1).padStart(6)} ${m.p90.toFixed(1).padStart(7)} ${m.gpuMs.toFixed(1).padStart(7)} ${String(m.triangles).padStart(10)}  ${goal}`);
      }
    }
    return true;
  } finally {
    await browser.close();
    server.close();
  }
}
