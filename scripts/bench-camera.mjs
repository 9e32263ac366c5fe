// The playground with its camera on, for `npm run bench` (alone:
// `npm run bench -- --camera`): headless Chromium, software rendering
// (SwiftShader), 1280×800, a fake camera playing the still of a real person
// (tests/data/camera/kinect-wave-still.mjpeg), the human-reach example with
// its person driven by the pose estimator (MoveNet Lightning on
// TensorFlow.js's wasm backend, in a worker). Per window: the playground's
// frames per second and the estimator's poses per second, the model's time
// per pose and the end-to-end latency (capture → pose → step). Goals: ≥ 30
// fps and ≥ 10 Hz. A measurement beside a goal, not a test: the machine is
// shared.
import os from 'node:os';
import path from 'node:path';
import { repo } from './lib.mjs';
import { serve } from './serve.mjs';
import { buildWasm } from './build.mjs';
import { cores, sample } from './bench-frames.mjs';

const CLIP = path.join(repo, 'tests', 'data', 'camera', 'kinect-wave-still.mjpeg');
const WINDOWS = 5;

/** The live figures of the page: poses per second, the model's ms, the latency. */
const live = (page) => page.evaluate(() => {
  const l = window.playground.app.live;
  return { rate: l.feed.rate, modelMs: l.poseMs, latencyMs: l.feed.latencyMs, given: l.feed.given };
});

/** The playground's own work per frame on the page's thread (its steps and drawing calls, ms). */
const own = (page) => page.evaluate(() => {
  const { stepMs, drawMs } = window.playground.app.stats;
  return { pageMs: stepMs + drawMs };
});

const median = (xs) => xs.slice().sort((a, b) => a - b)[Math.floor(xs.length / 2)];

/** Prints the table; returns false when the camera could not be measured. */
export async function cameraTable({ backends = ['webgpu', 'webgl2'] } = {}) {
  if (buildWasm('web') !== 0) return false;
  const { launch } = await import('../tests/browser/chromium.mjs');
  const { server, url } = await serve({ port: 0 });
  console.log('\n=== the playground with the camera on: headless Chromium, software rendering, 1280×800, fake camera (a still of a person),');
  console.log(`human-reach driven by MoveNet Lightning (TensorFlow.js wasm backend, in a worker); medians of ${WINDOWS} windows; ${cores()} cores;`);
  console.log('per frame: CPU ms of all the browser\'s processes, page ms the playground\'s steps and drawing calls; the model\'s ms measured in its worker');
  const load = () => os.loadavg().map((x) => x.toFixed(2)).join(' ');
  const before = load();
  console.log(`${'backend'.padEnd(8)} ${'fps'.padStart(6)} ${'p90 ms'.padStart(7)} ${'CPU ms'.padStart(7)} ${'page ms'.padStart(8)} ${'pose Hz'.padStart(8)} ${'model ms'.padStart(9)} ${'latency ms'.padStart(11)}  goal`);
  try {
    for (const backend of backends) {
      const browser = await launch({ webgpu: backend === 'webgpu', viewport: { width: 1280, height: 800 },
        extraArgs: ['--use-fake-ui-for-media-stream', '--use-fake-device-for-media-stream', `--use-file-for-fake-video-capture=${CLIP}`] });
      try {
        const page = await browser.context.newPage();
        await page.goto(`${url}?scenario=human-reach&backend=${backend}`);
        await page.evaluate(() => window.playground.ready);
        // The same scene with the camera off first: what the camera costs is the difference.
        await page.waitForTimeout(1000);
        const off = [];
        for (let w = 0; w < WINDOWS; w++) off.push({ ...(await sample(page, browser.profile, 1)), ...(await own(page)) });
        const medOff = (key) => median(off.map((r) => r[key]));
        console.log(`${backend.padEnd(8)} ${medOff('fps').toFixed(1).padStart(6)} ${medOff('p90').toFixed(1).padStart(7)} ${medOff('cpuMs').toFixed(1).padStart(7)} ${medOff('pageMs').toFixed(1).padStart(8)} ${'-'.padStart(8)} ${'-'.padStart(9)} ${'-'.padStart(11)}  (camera off)`);
        await page.click('#camera');
        await page.waitForFunction(() => window.playground.app.live.state !== 'starting' && (window.playground.app.live.state !== 'running' || window.playground.app.live.feed.given >= 5), null, { timeout: 180_000 });
        if ((await page.evaluate(() => window.playground.app.live.state)) !== 'running') {
          console.log(`${backend.padEnd(8)} the camera did not start: ${await page.evaluate(() => window.playground.app.root.querySelector('#camera-message')?.textContent)}`);
          continue;
        }
        const rows = [];
        for (let w = 0; w < WINDOWS; w++) {
          const m = await sample(page, browser.profile, 1);
          rows.push({ ...m, ...(await live(page)), ...(await own(page)) });
        }
        const med = (key) => median(rows.map((r) => r[key]));
        const fps = med('fps');
        const hz = med('rate');
        const goal = `≥ 30 fps (${fps >= 30 ? 'met' : 'NOT met'}), ≥ 10 Hz (${hz >= 10 ? 'met' : 'NOT met'})`;
        console.log(`${backend.padEnd(8)} ${fps.toFixed(1).padStart(6)} ${med('p90').toFixed(1).padStart(7)} ${med('cpuMs').toFixed(1).padStart(7)} ${med('pageMs').toFixed(1).padStart(8)} ${hz.toFixed(1).padStart(8)} ${med('modelMs').toFixed(1).padStart(9)} ${med('latencyMs').toFixed(0).padStart(11)}  ${goal}`);
      } finally {
        await browser.close();
      }
    }
    console.log(`load average (1, 5, 15 min) before the table: ${before}; after it: ${load()}`);
    return true;
  } finally {
    server.close();
  }
}

if (process.argv[1] && path.resolve(process.argv[1]) === path.join(repo, 'scripts', 'bench-camera.mjs')) {
  process.exit((await cameraTable()) ? 0 : 1);
}
