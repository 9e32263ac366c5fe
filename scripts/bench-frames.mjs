// The playground's frame rate in headless Chromium, for `npm run bench`:
// every example on WebGPU and on WebGL2 (both software-rendered here, by
// SwiftShader), 1280×800, running. Per example and backend: the median over
// a few windows of the frames per second (and of those, the frames that
// drew a new picture: a frame whose scene is the one on screen is not drawn
// again), the 90th percentile of the frame
// interval, the CPU time Chromium's GPU process spent per frame (Linux
// only: read from /proc), the playground's own work per frame on the
// page's thread (its steps and drawing calls, from its stats) and the
// triangles drawn; on WebGPU the same again with the view dragged a pixel
// to and fro every frame, so that every frame draws (an example that has
// settled would otherwise draw next to nothing). An example on the Panda
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

export const WINDOW_MS = 3000;
const WINDOWS = 3;

/**
 * CPU seconds so far of the browser launched with profile folder `profile`:
 * `{ gpu, all }`, its GPU process and all its processes (the browser, the
 * GPU process, the renderers and utilities: the descendants of the process
 * whose command line names the profile). Other browsers on the machine are
 * not counted. `null` off Linux (read from /proc).
 */
export function browserSeconds(profile) {
  if (!fs.existsSync('/proc/self/stat')) return null;
  const procs = [];
  for (const pid of fs.readdirSync('/proc').filter((p) => /^\d+$/.test(p))) {
    try {
      const cmdline = fs.readFileSync(`/proc/${pid}/cmdline`, 'utf8');
      // After the command name: state, ppid, ..., utime and stime (fields 14 and 15).
      const fields = fs.readFileSync(`/proc/${pid}/stat`, 'utf8').split(') ')[1].split(' ');
      procs.push({ pid, ppid: fields[1], cmdline, seconds: (Number(fields[11]) + Number(fields[12])) / 100 });
    } catch {
      // The process ended between the listing and the read.
    }
  }
  const ours = new Set(procs.filter((p) => p.cmdline.includes(`--user-data-dir=${profile}`)).map((p) => p.pid));
  for (let grew = true; grew;) {
    grew = false;
    for (const p of procs) {
      if (!ours.has(p.pid) && ours.has(p.ppid)) {
        ours.add(p.pid);
        grew = true;
      }
    }
  }
  const mine = procs.filter((p) => ours.has(p.pid));
  const sum = (ps) => ps.reduce((t, p) => t + p.seconds, 0);
  return { gpu: sum(mine.filter((p) => p.cmdline.includes('--type=gpu-process'))), all: sum(mine) };
}

/**
 * rAF timestamps of `page` over `ms` milliseconds, and the frames its
 * playground's viewer presented between the first and the last of them
 * (`null` on a page without the playground).
 */
const timestamps = (page, ms) => page.evaluate((ms) => new Promise((resolve) => {
  const presented = () => window.playground?.app?.viewer?.state?.().framesDrawn ?? null;
  const ts = [];
  let first = null;
  const tick = (t) => {
    if (ts.length === 0) first = presented();
    ts.push(t);
    if (t - ts[0] < ms) requestAnimationFrame(tick);
    else {
      const last = presented();
      resolve({ ts, drawn: first === null || last === null ? null : last - first });
    }
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

/**
 * One example on one backend: `sample`'s figures, the triangles drawn and
 * the page's own work per frame. `files`: a mesh row's (`meshRowFiles`).
 * With `drag`, also `dragged`: `sample`'s figures while the view is dragged
 * to and fro by a pixel every frame (as a person panning it), so that
 * every frame draws a new picture even where the example has settled.
 */
export async function measure(page, profile, url, name, backend, { files = null, windows = WINDOWS, drag = false } = {}) {
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
  const m = await sample(page, profile, windows);
  const { triangles, pageMs } = await page.evaluate(() => {
    const { stepMs, drawMs } = window.playground.app.stats;
    return { triangles: window.playground.state().triangles, pageMs: stepMs + drawMs };
  });
  if (!drag) return { ...m, triangles, pageMs };
  await page.evaluate(() => {
    window.benchDrag = true;
    const step = (k) => {
      if (!window.benchDrag) return;
      window.playground.app.viewer.pan(k % 2 ? 1 : -1, 0);
      requestAnimationFrame(() => step(k + 1));
    };
    step(0);
  });
  const dragged = await sample(page, profile, windows);
  await page.evaluate(() => { window.benchDrag = false; });
  return { ...m, triangles, pageMs, dragged };
}

/**
 * `{ fps, drawn, p90, gpuMs, cpuMs }` of the page as it runs (medians over
 * `windows` windows): frames per second, of which `drawn` per second
 * presented a new picture (the viewer leaves out a frame whose scene and
 * camera are those on screen; `null` on a page without the playground),
 * the 90th percentile of the frame interval, and the CPU milliseconds per
 * frame of the browser's GPU process and of all its processes (`profile`:
 * the browser's, see `browserSeconds`).
 */
export async function sample(page, profile, windows = WINDOWS) {
  const fps = [];
  const drawn = [];
  const p90 = [];
  const gpuMs = [];
  const cpuMs = [];
  for (let w = 0; w < windows; w++) {
    const cpu0 = browserSeconds(profile);
    const { ts, drawn: presented } = await timestamps(page, WINDOW_MS);
    const cpu1 = browserSeconds(profile);
    const gaps = ts.slice(1).map((t, k) => t - ts[k]).sort((a, b) => a - b);
    const seconds = (ts.at(-1) - ts[0]) / 1000;
    fps.push(gaps.length / seconds);
    if (presented !== null) drawn.push(presented / seconds);
    p90.push(gaps[Math.floor(0.9 * gaps.length)]);
    if (cpu0 !== null) {
      gpuMs.push((1000 * (cpu1.gpu - cpu0.gpu)) / gaps.length);
      cpuMs.push((1000 * (cpu1.all - cpu0.all)) / gaps.length);
    }
  }
  const m = (xs) => (xs.length ? median(xs) : NaN);
  return { fps: median(fps), drawn: drawn.length ? median(drawn) : null, p90: median(p90), gpuMs: m(gpuMs), cpuMs: m(cpuMs) };
}

/**
 * The ceiling that the machine and the browser set: a WebGPU canvas of the
 * playground's view size (read from the page), drawn through its
 * OffscreenCanvas like the view, that is only cleared each frame, on a page
 * that holds nothing else and loads no wasm. What an
 * example costs beyond it is the playground's.
 */
async function measureReference(page, profile, url) {
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
    // Drawn through its OffscreenCanvas, as the playground's view is.
    const context = canvas.transferControlToOffscreen().getContext('webgpu');
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
  return { ...(await sample(page, profile)), size: `${width}×${height}` };
}

const loadAverage = () => os.loadavg().map((x) => x.toFixed(2)).join(' ');

/** Cores this process may use. */
export const cores = () => os.availableParallelism?.() ?? os.cpus().length;

/** A table row: the figures of `m` (`sample`'s and `measure`'s), then `note`. */
function row(name, backend, m, note) {
  const ceiling = cores() * 1000 / m.cpuMs;
  const cells = [
    name.padEnd(20), backend.padEnd(8), m.fps.toFixed(1).padStart(6),
    (m.drawn === null ? '-' : m.drawn.toFixed(1)).padStart(8), m.p90.toFixed(1).padStart(7),
    m.gpuMs.toFixed(1).padStart(7), m.cpuMs.toFixed(1).padStart(7), ceiling.toFixed(0).padStart(8),
    (m.pageMs === undefined ? '-' : m.pageMs.toFixed(1)).padStart(8), String(m.triangles ?? 0).padStart(10),
  ];
  return `${cells.join(' ')}  ${note}`;
}

/**
 * The shipped examples and the mesh rows, as `{ name, example, files }`
 * (only those named in `only` when given).
 */
export function frameRows(examples, only = null) {
  const rows = [
    ...examples.map((name) => ({ name, example: name, files: null })),
    ...MESH_ROWS.map((r) => ({ name: r.name, example: r.example, files: meshRowFiles(r) })),
  ];
  return only ? rows.filter((r) => only.includes(r.name)) : rows;
}

/**
 * Prints the frame-rate table (the rows named in `only`, else all); returns
 * false when the page could not be measured.
 */
export async function frameTable(examples, only = null) {
  if (buildWasm('web') !== 0) return false;
  const { launch } = await import('../tests/browser/chromium.mjs');
  const { server, url } = await serve({ port: 0 });
  const browser = await launch({ webgpu: true, viewport: { width: 1280, height: 800 } });
  try {
    const page = await browser.context.newPage();
    console.log('\n=== playground frame rate: headless Chromium, software rendering (SwiftShader), 1280×800, running');
    console.log(`(median of ${WINDOWS} windows of ${WINDOW_MS / 1000} s, per frame: GPU ms = CPU time of Chromium's GPU process, CPU ms = of all its processes;`);
    console.log(` ≤ fps = ${cores()} cores × 1000 / CPU ms, the most this machine's cores allow for that work; page ms = the playground's own`);
    console.log(' work on the page\'s thread: the steps and the drawing calls; drawn/s = of the frames per second, those that drew a');
    console.log(' new picture: a frame whose scene and camera are those on screen (a settled arm, a stopped robot) is not drawn again;');
    console.log(' "view dragged": the same example, its view panned a pixel to and fro every frame, so that every frame is drawn)');
    const head = ['example'.padEnd(20), 'backend'.padEnd(8), 'fps'.padStart(6), 'drawn/s'.padStart(8), 'p90 ms'.padStart(7), 'GPU ms'.padStart(7),
      'CPU ms'.padStart(7), '≤ fps'.padStart(8), 'page ms'.padStart(8), 'triangles'.padStart(10)];
    console.log(`${head.join(' ')}  goal`);
    const before = loadAverage();
    const r = await measureReference(page, browser.profile, url);
    if (r) console.log(row('empty canvas', 'webgpu', r, `(reference: the ceiling here, a cleared ${r.size} canvas alone)`));
    const met = (fps) => (fps >= 50 ? 'met' : 'NOT met');
    for (const { name, example, files } of frameRows(examples, only)) {
      for (const backend of ['webgpu', 'webgl2']) {
        const webgpu = backend === 'webgpu';
        const m = await measure(page, browser.profile, url, example, backend, { files, drag: webgpu });
        console.log(row(name, backend, m, webgpu ? `≥ 50 fps (${met(m.fps)})` : '(reported)'));
        if (m.dragged) console.log(row(`  view dragged`, backend, { ...m.dragged, triangles: m.triangles }, `≥ 50 fps (${met(m.dragged.fps)})`));
      }
    }
    console.log(`load average (1, 5, 15 min) before the table: ${before}; after it: ${loadAverage()} on ${cores()} cores (the measurement itself keeps about two busy; more before it is other work)`);
    return true;
  } finally {
    await browser.close();
    server.close();
  }
}
