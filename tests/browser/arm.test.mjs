// The planar 3-link arm of the default scenario drawn by the wgpu renderer on
// each backend, its initial pose set by a slider with real mouse input, the
// camera driven by the mouse, and the failures shown on the page.
//
// Screenshots go to tests/artifacts/ (git-ignored): look at them.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { serve } from '../../scripts/serve.mjs';
import { launch, collectErrors, frames, repo, artifacts } from './chromium.mjs';
import { decodePng, pixel, BACKGROUND, colourDistance } from './png.mjs';



let server;
let baseUrl;

before(async () => {
  fs.mkdirSync(artifacts, { recursive: true });
  ({ server, url: baseUrl } = await serve({ port: 0 }));
});

after(() => new Promise((resolve) => server.close(resolve)));

/** The text boxes over the view (stats, HUD), in canvas pixels: the arm may pass under them. */
let overlays = [];
const underOverlay = ([x, y]) => overlays.some((r) => x >= r.x - 4 && x <= r.x + r.width + 4 && y >= r.y - 4 && y <= r.y + r.height + 4);

/** Points along every link of the arm, in canvas pixels (quarter, half, three quarters), not under the text boxes. */
function linkPoints(screenNodes) {
  const points = [];
  for (let i = 0; i + 1 < screenNodes.length; i++) {
    const [a, b] = [screenNodes[i], screenNodes[i + 1]];
    for (const t of [0.3, 0.5, 0.7]) points.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
  }
  return points.filter((p) => !underOverlay(p));
}

async function screenshot(page, name) {
  const png = await page.locator('#view').screenshot();
  fs.writeFileSync(path.join(artifacts, name), png);
  return decodePng(png);
}

for (const backend of ['webgpu', 'webgl2']) {
  test(`planar arm is drawn and follows a slider (${backend})`, async () => {
    const browser = await launch({ webgpu: true });
    try {
      const page = await browser.context.newPage();
      const errors = collectErrors(page);
      await page.goto(`${baseUrl}?backend=${backend}`);
      await page.evaluate(() => window.playground.ready);
      assert.equal(await page.evaluate(() => window.playground.backend), backend);
      // Pause the simulation: this test is about drawing and input.
      await page.locator('#run').click();
      await frames(page, 3);

      const before = await page.evaluate(() => window.playground.state());
      assert.equal(before.backend, backend);
      assert.equal(before.dof, 3);
      assert.equal(before.view, 'top', 'a planar arm gets the 2D top view');
      assert.equal(before.offscreenCanvas, true, 'the element draws through its canvas\'s OffscreenCanvas');
      assert.equal(before.screenNodes.length, 4);
      const box = await page.locator('#view').boundingBox();
      assert.equal(Math.round(box.width), before.width, 'device pixel ratio 1: CSS px = buffer px');

      // Picking: the ray through the end effector's pixel passes through it.
      const tip = before.nodes[3];
      const ray = await page.evaluate(([x, y]) => window.playground.viewer.rayAt(x, y), before.screenNodes[3]);
      const rel = tip.map((t, k) => t - ray.origin[k]);
      const along = rel.reduce((acc, r, k) => acc + r * ray.direction[k], 0);
      const miss = Math.hypot(...rel.map((r, k) => r - along * ray.direction[k]));
      assert.ok(along > 0 && miss < 2e-3, `ray misses the end effector by ${miss} m`);

      await page.screenshot({ path: path.join(artifacts, `page-${backend}.png`) });
      const shot1 = await screenshot(page, `arm-${backend}-1-start.png`);
      // The background reads the same colour on both backends (surface format handled).
      assert.ok(colourDistance(pixel(shot1, 3, 3), BACKGROUND) <= 6,
        `background ${pixel(shot1, 3, 3)} is not ${BACKGROUND}`);
      const viewBox = await page.locator('#view').boundingBox();
      overlays = [];
      for (const sel of ['#stats', '#hud']) {
        const r = await page.locator(sel).boundingBox();
        if (r) overlays.push({ ...r, x: r.x - viewBox.x, y: r.y - viewBox.y });
      }
      const armBefore = linkPoints(before.screenNodes);
      for (const [x, y] of armBefore) {
        const c = pixel(shot1, x, y);
        assert.ok(colourDistance(c, BACKGROUND) > 60, `no arm at (${x.toFixed(0)}, ${y.toFixed(0)}): ${c}`);
      }

      // Real input: click three quarters along the first joint's initial-pose slider (≈ +π/2).
      const slider = page.locator('#joint-0');
      await slider.scrollIntoViewIfNeeded();
      const sb = await slider.boundingBox();
      await page.mouse.click(sb.x + 0.75 * sb.width, sb.y + sb.height / 2);
      await frames(page, 3);
      const after = await page.evaluate(() => window.playground.state());
      assert.ok(after.q[0] > 1.0 && after.q[0] < 2.2, `q1 = ${after.q[0]}`);
      const shot2 = await screenshot(page, `arm-${backend}-2-moved.png`);

      let changed = 0;
      for (const [x, y] of armBefore) {
        if (colourDistance(pixel(shot1, x, y), pixel(shot2, x, y)) > 60) changed += 1;
      }
      assert.ok(changed >= armBefore.length - 1, `only ${changed}/${armBefore.length} arm pixels changed`);
      for (const [x, y] of linkPoints(after.screenNodes)) {
        const c = pixel(shot2, x, y);
        assert.ok(colourDistance(c, BACKGROUND) > 60, `moved arm missing at (${x.toFixed(0)}, ${y.toFixed(0)}): ${c}`);
      }

      // The 3D view draws too (orbit camera, perspective).
      await page.selectOption('#view-select', '3d');
      await frames(page, 3);
      const shot3 = await screenshot(page, `arm-${backend}-3-orbit.png`);
      const state3 = await page.evaluate(() => window.playground.state());
      assert.equal(state3.view, '3d');
      const [mx, my] = linkPoints(state3.screenNodes)[1];
      assert.ok(colourDistance(pixel(shot3, mx, my), BACKGROUND) > 60, 'arm missing in the 3D view');

      // Camera input with the real mouse: a drag orbits, the wheel zooms in.
      const cb = await page.locator('#view').boundingBox();
      await page.mouse.move(cb.x + 200, cb.y + 200);
      await page.mouse.down();
      await page.mouse.move(cb.x + 300, cb.y + 230, { steps: 5 });
      await page.mouse.up();
      await frames(page, 2);
      const orbited = await page.evaluate(() => window.playground.state());
      const tipMoved = Math.hypot(
        orbited.screenNodes[3][0] - state3.screenNodes[3][0],
        orbited.screenNodes[3][1] - state3.screenNodes[3][1],
      );
      assert.ok(tipMoved > 20, `orbit moved the end effector only ${tipMoved} px on screen`);
      const span = (s) => Math.hypot(s.screenNodes[3][0] - s.screenNodes[0][0], s.screenNodes[3][1] - s.screenNodes[0][1]);
      await page.mouse.wheel(0, -400);
      await frames(page, 2);
      const zoomed = await page.evaluate(() => window.playground.state());
      assert.ok(span(zoomed) > 1.2 * span(orbited), `zoom: ${span(orbited)} -> ${span(zoomed)} px`);
      await screenshot(page, `arm-${backend}-4-camera.png`);

      // The canvas's drawing belongs to its viewer: a second viewer on it is
      // refused with an Error that says why, and the first one draws on.
      const second = await page.evaluate(async (backend) => {
        const app = window.playground.app;
        try {
          (await app.wasm.Viewer.create(app.canvas, { backend, offscreen: true })).free();
          return 'created';
        } catch (e) {
          return `${e instanceof Error}: ${e.message}`;
        }
      }, backend);
      assert.match(second, /^true: the canvas cannot be drawn on: its drawing could not be handed over \([^\n]+\) nor drawn on directly; .*: give each viewer a canvas of its own$/);
      const drawn = zoomed.framesDrawn;
      await page.mouse.wheel(0, 200);
      await page.waitForFunction((n) => window.playground.state().framesDrawn > n, drawn);
      const unzoomed = await page.evaluate(() => window.playground.state());
      assert.ok(span(unzoomed) < span(zoomed), `the first viewer still draws: ${span(zoomed)} -> ${span(unzoomed)} px`);

      const status = await page.locator('#page-status').textContent();
      assert.match(status, backend === 'webgpu' ? /WebGPU/ : /WebGL2/);
      assert.equal(await page.locator('#error').isHidden(), true);
      assert.deepEqual(errors, []);
    } finally {
      await browser.close();
    }
  });
}

test('without WebGPU, asking for it shows a readable error on the page', async () => {
  const browser = await launch({ webgpu: false });
  try {
    const page = await browser.context.newPage();
    await page.goto(`${baseUrl}?backend=webgpu`);
    const failure = await page.evaluate(() => window.playground.ready.then(() => null, (e) => String(e.message ?? e)));
    assert.ok(failure, 'ready should reject');
    const box = page.locator('#error');
    assert.equal(await box.isVisible(), true);
    const text = await box.textContent();
    assert.match(text, /could not start/);
    assert.match(text, /WebGPU/);
    await page.locator('skeleton-playground').screenshot({ path: path.join(artifacts, 'no-webgpu-error.png') });
  } finally {
    await browser.close();
  }
});

test('the page falls back to WebGL2 when WebGPU is missing', async () => {
  const browser = await launch({ webgpu: false });
  try {
    const page = await browser.context.newPage();
    const errors = collectErrors(page);
    await page.goto(baseUrl);
    await page.evaluate(() => window.playground.ready);
    assert.equal(await page.evaluate(() => window.playground.backend), 'webgl2');
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
  }
});

test('a browser with WebGPU, but not on an OffscreenCanvas, draws with WebGL2 on it', async () => {
  const browser = await launch({ webgpu: true });
  try {
    await browser.context.addInitScript(() => {
      const getContext = OffscreenCanvas.prototype.getContext;
      OffscreenCanvas.prototype.getContext = function (type, ...rest) {
        return type === 'webgpu' ? null : getContext.call(this, type, ...rest);
      };
    });
    const page = await browser.context.newPage();
    const errors = collectErrors(page);
    await page.goto(baseUrl);
    await page.evaluate(() => window.playground.ready);
    const state = await page.evaluate(() => window.playground.state());
    assert.equal(state.backend, 'webgl2');
    assert.equal(state.offscreenCanvas, true);
    assert.ok(state.framesDrawn > 0, 'frames drawn');
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
  }
});

test('with neither WebGPU nor WebGL2 the page says so', async () => {
  const browser = await launch({ webgpu: false, extraArgs: ['--disable-3d-apis'] });
  try {
    // The flag leaves WebGL2 to an OffscreenCanvas in this Chromium: take it
    // from both kinds of canvas, as a browser without it would.
    await browser.context.addInitScript(() => {
      for (const Canvas of [HTMLCanvasElement, OffscreenCanvas]) {
        const getContext = Canvas.prototype.getContext;
        Canvas.prototype.getContext = function (type, ...rest) {
          return /^webgl/.test(type) ? null : getContext.call(this, type, ...rest);
        };
      }
    });
    const page = await browser.context.newPage();
    await page.goto(baseUrl);
    const failure = await page.evaluate(() => window.playground.ready.then(() => null, (e) => String(e.message ?? e)));
    assert.match(failure ?? '', /neither WebGPU nor WebGL2/);
    const text = await page.locator('#error').textContent();
    assert.match(text, /neither WebGPU nor WebGL2/);
    await page.locator('skeleton-playground').screenshot({ path: path.join(artifacts, 'no-graphics-error.png') });
  } finally {
    await browser.close();
  }
});

test('the Viewer rejects bad input with an Error naming the problem', async () => {
  const browser = await launch({ webgpu: false });
  try {
    const page = await browser.context.newPage();
    const errors = collectErrors(page);
    await page.goto(`${baseUrl}?backend=webgl2`);
    await page.evaluate(() => window.playground.ready);
    const messages = await page.evaluate(async () => {
      const { Viewer } = await import('/pkg/skeleton_avoidance.js');
      const v = window.playground.viewer;
      const message = (f) => {
        try {
          f();
          return null;
        } catch (e) {
          return e instanceof Error ? e.message : `not an Error: ${e}`;
        }
      };
      const rejection = (p) => p.then(() => null, (e) => (e instanceof Error ? e.message : `not an Error: ${e}`));
      return {
        shortQ: message(() => v.setJoints([0, 1])),
        nanQ: message(() => v.setJoints([0, NaN, 0])),
        stringQ: message(() => v.setJoints('0,0,0')),
        wordInQ: message(() => v.setJoints([0, 'x', 0])),
        preset: message(() => v.setRobot({ preset: 'nope' })),
        display: message(() => v.setDisplay({ volume: true })),
        displayType: message(() => v.setDisplay({ nodes: 'yes' })),
        displayArray: message(() => v.setDisplay([true])),
        view: message(() => v.setView('sideways')),
        zoom: message(() => v.zoom(0)),
        resize: message(() => v.resize(NaN, 10)),
        notCanvas: await rejection(Viewer.create(document.body, {})),
        backend: await rejection(Viewer.create(document.createElement('canvas'), { backend: 'vulkan' })),
        stillDrawing: v.state().q,
      };
    });
    assert.match(messages.shortQ, /q: expected 3 joint values, got 2/);
    assert.match(messages.nanQ, /q\[1\]: not a finite number/);
    assert.match(messages.stringQ, /q: expected an array or a Float64Array/);
    assert.match(messages.wordInQ, /q\[1\]: not a number/);
    assert.match(messages.preset, /robot\.preset: unknown robot "nope"/);
    assert.match(messages.display, /display\.volume: unknown field/);
    assert.match(messages.displayType, /display\.nodes: expected true or false, got the string "yes"/);
    assert.match(messages.displayArray, /display: expected an object/);
    assert.match(messages.view, /view: expected .*"sideways"/);
    assert.match(messages.zoom, /zoom\.factor: must be > 0/);
    assert.match(messages.resize, /width: not a finite number/);
    assert.match(messages.notCanvas, /canvas: not an HTMLCanvasElement/);
    assert.match(messages.backend, /options\.backend: expected .*"vulkan"/);
    assert.deepEqual(messages.stillDrawing, [0, 0, 0], 'a rejected input leaves the state untouched');
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
  }
});
