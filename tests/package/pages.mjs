// The pages of the package layer: a small app that uses the library and the
// element, its HTML, the size budgets of the bundles, and the check that a
// page runs in Chromium (tests/package/bundlers.test.mjs, compat.test.mjs).
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import zlib from 'node:zlib';
import { serve } from '../../scripts/serve.mjs';
import { artifacts, launch } from '../browser/chromium.mjs';
import { decodePng } from '../browser/png.mjs';

/**
 * Gzipped bytes of the JS a bundle loads (every .js under `dir`, the study
 * worker included). A compat bundle carries the wasm in its JS, as base64,
 * which gzips to about 1.35 times the gzipped binary: 2.32 MB for the 1.72 MB
 * module, 2.37 MB for the whole esbuild bundle with the element (measured
 * 2026-11-24). Vite also bundles the study worker (the Monte Carlo panel of
 * controls="full") with a copy of its own, fetched only when a study runs:
 * 4.71 MB in all, of which the page loads half. The compat budgets follow
 * the wasm's: 1.38 × `WASM_BUDGET` plus the element (2.575 MB), twice that
 * for Vite's two copies (5.15 MB); measured 2026-11-28 with the module at
 * 1.820 MB: 2.509 MB (esbuild) and 4.97 MB (Vite); 2026-11-29 with the
 * module at 1.852 MB: 2.548 MB (esbuild).
 */
export const JS_BUDGET = { vite: 90_000, webpack: 90_000, esbuild: 70_000, 'esbuild compat': 2_575_000, 'vite compat': 5_150_000 };
/** Gzipped bytes of the wasm (the module with the renderer). */
export const WASM_BUDGET = 1_860_000;

export const app = (from = 'skeleton-avoidance') => `
import { World, simulate, exampleScenario, presetNames } from '${from}';
import '${from}/element';

const scenario = exampleScenario('human-panda');
const trace = simulate({ ...scenario, duration: 0.05 });
const world = new World(scenario);
world.advance(0.001, 20);
window.result = { samples: trace.samples.length, t: world.time, presets: presetNames() };
world.free();
`;

export const HTML = (script) => `<!doctype html>
<html lang="en">
<head><meta charset="utf-8"><title>consumer</title><link rel="icon" href="data:,">
<style>skeleton-playground { display: block; width: 640px; height: 400px; }</style></head>
<body>
<skeleton-playground id="pg" scenario="human-panda" controls="minimal" autoplay></skeleton-playground>
${script}
</body>
</html>
`;

/** Gzipped size of every file with extension `ext` under `dir`. */
export function gzipped(dir, ext) {
  let total = 0;
  for (const entry of fs.readdirSync(dir, { recursive: true })) {
    const file = path.join(dir, entry);
    if (entry.endsWith(ext) && fs.statSync(file).isFile()) total += zlib.gzipSync(fs.readFileSync(file), { level: 6 }).length;
  }
  return total;
}

/** Checks a bundle's sizes; `inlined`: the wasm is in the JS, and no .wasm file may be there. */
export function checkBudget(name, dist, { inlined = false } = {}) {
  const js = gzipped(dist, '.js');
  const wasm = gzipped(dist, '.wasm');
  console.log(`# ${name}: JS ${(js / 1e3).toFixed(1)} kB gzipped (budget ${JS_BUDGET[name] / 1e3} kB), wasm ${(wasm / 1e6).toFixed(3)} MB gzipped`);
  assert.ok(js > 0 && js <= JS_BUDGET[name], `${name}: JS ${js} B gzipped, budget ${JS_BUDGET[name]} B`);
  if (inlined) assert.equal(wasm, 0, `${name}: the bundle holds a .wasm file`);
  else assert.ok(wasm > 0 && wasm <= WASM_BUDGET, `${name}: wasm ${wasm} B gzipped (one copy expected), budget ${WASM_BUDGET} B`);
}

/**
 * Opens `url` in Chromium and checks the app and the element: `simulate` and
 * `World` ran, the element's world advanced (waiting for simulated time, not
 * for wall time), its viewer drew triangles and the canvas shows more than
 * the background; no failed request, no console error.
 */
export async function checkPage(url, label) {
  const browser = await launch({ webgpu: false, viewport: { width: 800, height: 600 } });
  try {
    const page = await browser.context.newPage();
    const problems = [];
    page.on('console', (msg) => { if (msg.type() === 'error') problems.push(`console: ${msg.text()}`); });
    page.on('pageerror', (err) => problems.push(`pageerror: ${err.message}`));
    page.on('response', (res) => { if (res.status() >= 400) problems.push(`HTTP ${res.status()} ${res.url()}`); });
    page.on('requestfailed', (req) => problems.push(`failed request ${req.url()}`));
    await page.goto(url);
    await page.waitForFunction(() => window.result !== undefined || document.getElementById('pg')?.shadowRoot?.textContent.includes('could not start'), null, { timeout: 60_000 });
    const result = await page.evaluate(() => window.result);
    assert.ok(result, `${label}: the app did not run: ${problems.join('\n')}`);
    assert.equal(result.samples > 0, true, `${label}: simulate returned no samples`);
    assert.ok(Math.abs(result.t - 0.02) < 1e-12, `${label}: World.time ${result.t}`);
    assert.ok(result.presets.includes('panda'), `${label}: presets ${result.presets}`);
    await page.evaluate(() => document.getElementById('pg').ready);
    await page.waitForFunction(() => (document.getElementById('pg').playground.world?.time ?? 0) >= 0.2, null, { timeout: 60_000 });
    const drawn = await page.evaluate(() => {
      const pg = document.getElementById('pg').playground;
      return { triangles: pg.viewer.state().triangles, robot: pg.world.state().skeleton.nodes.length };
    });
    assert.ok(drawn.triangles > 100 && drawn.robot > 5, `${label}: ${JSON.stringify(drawn)}`);
    const png = await page.locator('#pg').screenshot();
    fs.mkdirSync(artifacts, { recursive: true });
    fs.writeFileSync(path.join(artifacts, `package-${label.replace(/\W+/g, '-')}.png`), png);
    const shot = decodePng(png);
    const colours = new Set();
    for (let i = 0; i < shot.data.length; i += 4 * 7) colours.add((shot.data[i] << 16) | (shot.data[i + 1] << 8) | shot.data[i + 2]);
    assert.ok(colours.size > 20, `${label}: the element shows ${colours.size} colours`);
    assert.deepEqual(problems, [], label);
    console.log(`# ${label}: simulate ${result.samples} samples, element ${drawn.triangles} triangles, ${colours.size} colours`);
  } finally {
    await browser.close();
  }
}

export async function served(root, fn) {
  const { server, url } = await serve({ port: 0, root });
  try {
    await fn(url);
  } finally {
    await new Promise((resolve) => server.close(resolve));
  }
}
