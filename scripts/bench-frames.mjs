// The playground's frame rate in headless Chromium, for `npm run bench`:
// every example on WebGPU and on WebGL2 (both software-rendered here, by
// SwiftShader), 1280×800, running. Per example and backend: the median over
// a few windows of the frames per second, the 90th percentile of the frame
// interval, the CPU time Chromium's GPU process spent per frame (Linux
// only: read from /proc), the playground's own work per frame on the
// page's thread (its steps and drawing calls, from its stats) and the
// triangles drawn. An example on the Panda
// or UR5 preset is measured once its meshes are drawn (the playground
// fetches them, web/preset-meshes.js). Then a heavier mesh, the iiwa 14's,
// in the human-panda scene (MESH_ROWS). First comes a reference row: a
// cleared WebGPU canvas of the same size alone, the ceiling that this
// machine and browser set whatever the playground does. The load average is
// printed beside the table: the machine is shared. A frame rate depends on
// the machine: this is a measurement with a goal beside it, not a test.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { repo } from './lib.mjs';
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

/**
 * Robots drawn with their collision meshes (crate/tests/data, licences
 * there) in an example's scene: the URDF, fitted to its meshes, replaces the
 * example's robot (its obstacles, task and controller kept), and the viewer
 * draws the meshes under the volumes.
 */
const MESH_ROWS = [
  { name: 'iiwa14+meshes', example: 'human-panda', urdf: 'iiwa14_mesh_collision.urdf', meshes: 'iiwa14/collision' },
];

/** `{ xml, meshes: { path: base64 } }` of a mesh row. */
function meshRowFiles(row) {
  const data = path.join(repo, 'crate', 'tests', 'data');
  const dir = path.join(data, 'meshes', row.meshes);
  const meshes = Object.fromEntries(fs.readdirSync(dir).filter((f) => /\.stl$/i.test(f))
    .map((f) => [`${row.meshes}/${f}`, fs.readFileSync(path.join(dir, f)).toString('base64')]));
  return { xml: fs.readFileSync(path.join(data, 'urdf', row.urdf), 'utf8'), meshes, tip: row.tip };
}

/** Replaces the page's robot by a mesh row's URDF with its meshes drawn (after the example loaded). */
const withMeshes = (page, files) => page.evaluate(({ xml, meshes, tip }) => {
  const app = window.playground.app;
  const bytes = Object.fromEntries(Object.entries(meshes).map(([k, b64]) => [k, Uint8Array.from(atob(b64), (c) => c.charCodeAt(0))]));
  const options = { meshes: bytes, ...(tip ? { tip } : {}) };
  const fit = app.wasm.fitUrdf(xml, options);
  if (fit.problems.length) throw new Error(fit.problems.join('; '));
  if (app.loadScenario({ ...app.scenario, robot: fit.robot }, 'with meshes')) throw new Error('the scenario with the URDF robot was refused');
  app.viewer.setUrdf(xml, options);
  // setUrdf sets a robot, which resets the camera: the scenario's again.
  if (app.scenario.camera) app.viewer.setCamera(app.scenario.camera);
  app.drawWorld();
  app.fit();
}, files);

/** One example on one backend: `{ fps, p90, gpuMs, triangles }` (medians over the windows). */
async function measure(page, url, name, backend, files = null) {
  await page.goto(`${url}?scenario=${name}&backend=${backend}`);
  await page.evaluate(() => window.playground.ready);
  if (files) await withMeshes(page, files);
  else {
    // A preset with meshes: measured with them drawn.
    await page.waitForFunction(() => {
      const app = window.playground.app;
      const robot = app.scenario.robot;
      const preset = typeof robot === 'string' ? robot : robot?.preset;
      return !['iiwa14', 'panda', 'ur5'].includes(preset) || app.presetMeshesShown === preset;
    }, null, { timeout: 60000 });
  }
  await page.waitForTimeout(1000);
  const m = await sample(page);
  const { triangles, pageMs } = await page.evaluate(() => {
    const { stepMs, drawMs } = window.playground.app.stats;
    return { triangles: window.playground.state().triangles, pageMs: stepMs + drawMs };
  });
  return { ...m, triangles, pageMs };
}

/** `{ fps, p90, gpuMs }` of the page as it runs: medians over the windows. */
async function sample(page) {
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
  return { fps: median(fps), p90: median(p90), gpuMs: gpuMs.length ? median(gpuMs) : NaN };
}

/**
 * The ceiling that the machine and the browser set: a WebGPU canvas of the
 * playground's view size (read from the page) that is only cleared each
 * frame, on a page that holds nothing else and loads no wasm. What an
 * example costs beyond it is the playground's.
 */
async function measureReference(page, url) {
  await page.goto(`${url}?scenario=planar-transition&backend=webgpu&paused`);
  await page.evaluate(() => window.playground.ready);
  const { width, height } = await page.evaluate(() => window.playground.state());
  // Any page of the server's origin: WebGPU needs a secure context.
  await page.goto(`${url}reference-canvas`);
  const ok = await page.evaluate(async ({ width, height }) => {
    const adapter = await navigator.gpu?.requestAdapter();
    if (!adapter) return false;
    const device = await adapter.requestDevice();
    document.body.replaceChildren();
    document.body.style.margin = '0';
    const canvas = document.createElement('canvas');
    Object.assign(canvas, { width, height });
    canvas.style.cssText = `display:block;width:${width}px;height:${height}px`;
    document.body.append(canvas);
    const context = canvas.getContext('webgpu');
    context.configure({ device, format: 'rgba8unorm', alphaMode: 'opaque' });
    const frame = () => {
      const encoder = device.createCommandEncoder();
      encoder.beginRenderPass({
        colorAttachments: [{ view: context.getCurrentTexture().createView(), loadOp: 'clear', storeOp: 'store', clearValue: { r: 0.95, g: 0.96, b: 0.98, a: 1 } }],
      }).end();
      device.queue.submit([encoder.finish()]);
      requestAnimationFrame(frame);
    };
    requestAnimationFrame(frame);
    return true;
  }, { width, height });
  if (!ok) return null;
  await page.waitForTimeout(1000);
  return { ...(await sample(page)), size: `${width}×${height}` };
}

const loadAverage = () => os.loadavg().map((x) => x.toFixed(2)).join(' ');

/** Prints the frame-rate table; returns false when the page could not be measured. */
export async function frameTable(examples) {
  if (buildWasm('web') !== 0) return false;
  const { launch } = await import('../tests/browser/chromium.mjs');
  const { server, url } = await serve({ port: 0 });
  const browser = await launch({ webgpu: true, viewport: { width: 1280, height: 800 } });
  try {
    const page = await browser.context.newPage();
    console.log('\n=== playground frame rate: headless Chromium, software rendering (SwiftShader), 1280×800, running');
    console.log(`(median of ${WINDOWS} windows of ${WINDOW_MS / 1000} s; GPU ms = CPU time of Chromium's GPU process per frame, on two cores;`);
    console.log(" page ms = the playground's own work per frame on the page's thread: the steps and the drawing calls)");
    console.log(`${'example'.padEnd(20)} ${'backend'.padEnd(8)} ${'fps'.padStart(6)} ${'p90 ms'.padStart(7)} ${'GPU ms'.padStart(7)} ${'page ms'.padStart(8)} ${'triangles'.padStart(10)}  goal`);
    const before = loadAverage();
    const r = await measureReference(page, url);
    if (r) {
      console.log(`${'empty canvas'.padEnd(20)} ${'webgpu'.padEnd(8)} ${r.fps.toFixed(1).padStart(6)} ${r.p90.toFixed(1).padStart(7)} ${r.gpuMs.toFixed(1).padStart(7)} ${'-'.padStart(8)} ${'0'.padStart(10)}  (reference: the ceiling here, a cleared ${r.size} canvas alone)`);
    }
    const rows = [
      ...examples.map((name) => ({ name, example: name, files: null })),
      ...MESH_ROWS.map((row) => ({ name: row.name, example: row.example, files: meshRowFiles(row) })),
    ];
    for (const { name, example, files } of rows) {
      for (const backend of ['webgpu', 'webgl2']) {
        const m = await measure(page, url, example, backend, files);
        const goal = backend === 'webgpu' ? `≥ 50 fps ${m.fps >= 50 ? '(met)' : '(NOT met)'}` : '(reported)';
        console.log(`${name.padEnd(20)} ${backend.padEnd(8)} ${m.fps.toFixed(1).padStart(6)} ${m.p90.toFixed(1).padStart(7)} ${m.gpuMs.toFixed(1).padStart(7)} ${m.pageMs.toFixed(1).padStart(8)} ${String(m.triangles).padStart(10)}  ${goal}`);
      }
    }
    console.log(`load average (1, 5, 15 min) before the table: ${before}; after it: ${loadAverage()} on ${os.cpus().length} cores (the measurement itself keeps about two busy; more before it is other work)`);
    return true;
  } finally {
    await browser.close();
    server.close();
  }
}
