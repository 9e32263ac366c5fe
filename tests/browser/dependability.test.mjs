// The Dependability panel: a Monte Carlo study of the scene in a Web Worker
// (progress, histogram, probabilities), a cancelled study that leaves the
// scene as it was, refused input, and the risk map over a horizontal plane.
//
// Screenshots (1280×800) go to tests/artifacts/ (git-ignored): look at them.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { serve } from '../../scripts/serve.mjs';
import { launch, collectErrors, frames, artifacts } from './chromium.mjs';

let server;
let baseUrl;

before(async () => {
  fs.mkdirSync(artifacts, { recursive: true });
  ({ server, url: baseUrl } = await serve({ port: 0 }));
});
after(() => new Promise((resolve) => server.close(resolve)));

/** The scene as a scenario, and the simulated time. */
const scene = (page) => page.evaluate(() => ({ s: window.playground.app.currentScenario(), t: window.playground.app.world.time }));

/** Pixels of `selector` (a canvas) by colour class: blue bars, red, green, other non-white. */
const pixels = (page, selector) => page.evaluate((sel) => {
  const c = document.querySelector('skeleton-playground')?.shadowRoot?.querySelector(sel) ?? document.querySelector(sel);
  const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  const colours = new Set();
  let blue = 0;
  for (let k = 0; k < d.length; k += 4) {
    if (d[k + 2] > 150 && d[k] < 100) blue += 1;
    colours.add(`${d[k] >> 4},${d[k + 1] >> 4},${d[k + 2] >> 4}`);
  }
  return { blue, colours: colours.size };
}, selector);

test('a small study shows its histogram and probabilities; Cancel leaves the scene as it was', async () => {
  const browser = await launch({ webgpu: true, viewport: { width: 1280, height: 800 } });
  try {
    const page = await browser.context.newPage();
    const errors = collectErrors(page);
    await page.goto(`${baseUrl}?scenario=chattering&paused`);
    await page.evaluate(() => window.playground.ready);
    await frames(page, 3);
    const before = await scene(page);

    // Refused input names the field and starts nothing.
    await page.locator('#study-runs').fill('0');
    await page.locator('#study-run').click();
    assert.match(await page.locator('#study-message').innerText(), /^runs: must be in 1\.\.1000/);
    await page.locator('#study-runs').fill('2000');
    await page.locator('#study-run').click();
    assert.match(await page.locator('#study-message').innerText(), /^runs: must be in 1\.\.1000/);

    await page.locator('#study-runs').fill('30');
    await page.locator('#study-duration').fill('0.5');
    await page.locator('#study-run').click();
    await page.locator('#study-histogram').waitFor({ state: 'visible', timeout: 120_000 });
    assert.match(await page.locator('#study-message').innerText(), /^30 runs in [0-9.]+ s/);
    const table = await page.locator('#study-table').innerText();
    assert.match(table, /chattering\s+100\.0 %/);
    assert.match(table, /contact while moving\s+0\.0 %/);
    const bars = await pixels(page, '#study-histogram');
    assert.ok(bars.blue > 200, `histogram bars: ${bars.blue} blue pixels`);
    const report = await page.evaluate(() => window.playground.app.study.report);
    assert.equal(report.runs, 30);
    assert.ok(report.minClearance.max > report.minClearance.min, 'noise gives a spread');
    await page.locator('#dependability').scrollIntoViewIfNeeded();
    await page.screenshot({ path: path.join(artifacts, 'dependability-study.png') });

    // A long study, cancelled half-way: nothing of the scene changed.
    await page.locator('#study-runs').fill('1000');
    await page.locator('#study-duration').fill('2');
    await page.locator('#study-run').click();
    await page.waitForFunction(() => {
      const m = document.querySelector('skeleton-playground')?.shadowRoot?.querySelector('#study-message') ?? document.querySelector('#study-message');
      return /^[1-9][0-9]* \/ 1000 runs/.test(m.textContent);
    }, null, { timeout: 60_000 });
    assert.equal(await page.locator('#study-progress').isVisible(), true);
    await page.locator('#study-cancel').click();
    assert.equal(await page.locator('#study-message').innerText(), 'Study cancelled; the scene is unchanged.');
    assert.equal(await page.locator('#study-progress').isVisible(), false);
    await frames(page, 5);
    assert.deepEqual(await scene(page), before);
    // the previous study's histogram is still there
    assert.equal(await page.locator('#study-histogram').isVisible(), true);
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
  }
});

test('the risk map is a non-uniform heat map of the clearance over the plane', async () => {
  const browser = await launch({ webgpu: true, viewport: { width: 1280, height: 800 } });
  try {
    const page = await browser.context.newPage();
    const errors = collectErrors(page);
    await page.goto(`${baseUrl}?scenario=lwr4-elbow&paused`);
    await page.evaluate(() => window.playground.ready);
    await frames(page, 3);
    const before = await scene(page);
    // Without a selection the plane cannot go through it.
    await page.locator('#risk-at-obstacle').click();
    assert.match(await page.locator('#risk-message').innerText(), /^Select an obstacle first/);
    // Select the ball (as the obstacle list does): the plane goes through
    // it; then map it at the elbow's height.
    await page.evaluate(() => window.playground.app.select('ball'));
    await page.locator('#risk-at-obstacle').click();
    const ballZ = (await scene(page)).s.obstacles[0].shape.center[2];
    assert.ok(Math.abs(Number(await page.locator('#risk-height').inputValue()) - ballZ) < 0.006, `plane at ${ballZ}`);
    await page.locator('#risk-height').fill('0.6');
    await page.locator('#risk-run').click();
    await page.locator('#risk-map').waitFor({ state: 'visible' });
    const map = await page.evaluate(() => window.playground.app.study.riskValues);
    assert.equal(map.values.length, 32 * 32);
    const [lo, hi] = [Math.min(...map.values), Math.max(...map.values)];
    assert.ok(lo <= 0 && hi > 0.3, `clearance from ${lo} to ${hi} m: contact near the arm, far elsewhere`);
    assert.match(await page.locator('#risk-message').innerText(), /“ball” placed at 32×32 points at z = 0\.60 m/);
    const heat = await pixels(page, '#risk-map');
    assert.ok(heat.colours > 10, `${heat.colours} colours`);
    assert.deepEqual(await scene(page), before, 'the map does not move the obstacle');
    await page.locator('#risk-map').scrollIntoViewIfNeeded();
    await page.screenshot({ path: path.join(artifacts, 'dependability-risk-map.png') });
    await page.locator('#risk-map').screenshot({ path: path.join(artifacts, 'risk-map.png') });

    // The switch probability (World.riskAt) over the same plane: 0 far
    // from the arm, high where two segments are about equally close.
    await page.locator('#risk-kind').selectOption('switchProbability');
    await page.locator('#risk-run').click();
    const risk = await page.evaluate(() => window.playground.app.study.riskValues);
    assert.equal(risk.kind, 'switchProbability');
    assert.ok(risk.values.every((p) => p >= 0 && p <= 1));
    const high = risk.values.filter((p) => p > 0.2).length;
    const zero = risk.values.filter((p) => p < 1e-6).length;
    assert.ok(high > 0 && zero > 100, `${high} cells above 0.2, ${zero} at 0`);
    assert.match(await page.locator('#risk-message').innerText(), /probability that the sensed closest segment/);
    await page.locator('#risk-map').scrollIntoViewIfNeeded();
    await page.screenshot({ path: path.join(artifacts, 'dependability-risk-switch.png') });
    assert.deepEqual(await scene(page), before);
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
  }
});

test('the docs page runs 200 noisy copies of the chattering example and draws them', async () => {
  const browser = await launch({ webgpu: true, viewport: { width: 1280, height: 800 } });
  try {
    const page = await browser.context.newPage();
    const errors = collectErrors(page);
    await page.goto(`${baseUrl}docs.html`);
    await page.locator('#docs-study-run').scrollIntoViewIfNeeded();
    await page.locator('#docs-study-run').click();
    await page.locator('#docs-study-table').waitFor({ state: 'visible', timeout: 180_000 });
    assert.match(await page.locator('#docs-study-message').innerText(), /^200 runs in [0-9.]+ s/);
    assert.match(await page.locator('#docs-study-table').innerText(), /stop\s+100\.0 %/);
    const bars = await pixels(page, '#docs-study-histogram');
    assert.ok(bars.blue > 500, `histogram bars: ${bars.blue} blue pixels`);
    await page.locator('#docs-study').scrollIntoViewIfNeeded();
    await page.screenshot({ path: path.join(artifacts, 'docs-study.png') });
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
  }
});
