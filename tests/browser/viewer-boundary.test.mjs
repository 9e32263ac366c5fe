// The browser bundle's `Viewer` behind the same typed boundary as `World`:
// numbers are checked for their JS type before wasm coerces them, objects are
// read once (a throwing getter or Proxy is one clean Error), `drawWorld`
// takes only a live World, and a freed Viewer throws `this Viewer has been
// freed` (a second free does nothing). A seeded hostile loop over every
// method then checks that only plain `Error`s naming a field come out and
// that the viewer keeps drawing.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { serve } from '../../scripts/serve.mjs';
import { launch, collectErrors } from './chromium.mjs';

let server;
let baseUrl;

before(async () => {
  ({ server, url: baseUrl } = await serve({ port: 0 }));
});
after(() => new Promise((resolve) => server.close(resolve)));

const SEED = Number(process.env.FUZZ_SEED ?? 13);
const CALLS = Number(process.env.VIEWER_FUZZ_CALLS ?? 3000);

test('the Viewer checks its arguments, reads them once and refuses use after free', async () => {
  const browser = await launch({ webgpu: false });
  try {
    const page = await browser.context.newPage();
    const errors = collectErrors(page);
    await page.goto(`${baseUrl}gallery.html?backend=webgl2&small=1`);
    await page.evaluate(() => window.galleryReady);
    const messages = await page.evaluate(async () => {
      const sa = await import('./pkg/skeleton_avoidance.js');
      const v = window.gallery.viewer;
      const said = (f) => {
        try {
          f();
          return 'accepted';
        } catch (e) {
          return `${e.constructor.name}: ${e.message}`;
        }
      };
      const world = new sa.World(sa.exampleScenario('planar-transition'));
      const freedWorld = new sa.World(sa.exampleScenario('planar-transition'));
      freedWorld.free();
      const out = {
        orbitString: said(() => v.orbit('1', 0)),
        orbitMissing: said(() => v.orbit(1)),
        zoomNaN: said(() => v.zoom(NaN)),
        resizeBool: said(() => v.resize(true, 100)),
        fitString: said(() => v.fit('0.8')),
        fitNone: said(() => v.fit()),
        fitTopString: said(() => v.fit(0.8, '10')),
        fitTopNegative: said(() => v.fit(0.8, -1)),
        fitTop: said(() => v.fit(0.8, 40)),
        rayAtArray: said(() => v.rayAt([1], 2)),
        drawWorldPlain: said(() => v.drawWorld({})),
        drawWorldFreed: said(() => v.drawWorld(freedWorld)),
        drawWorldLive: said(() => v.drawWorld(world)),
        jointsGetter: said(() => v.setJoints({ get length() { throw new Error('boom'); } })),
        displayProxy: said(() => v.setDisplay(new Proxy({}, { ownKeys() { throw new Error('trap'); } }))),
        renderAfter: said(() => v.render()),
      };
      world.free();
      v.free();
      out.renderFreed = said(() => v.render());
      out.backendFreed = said(() => v.backend);
      out.secondFree = said(() => v.free());
      return out;
    });
    assert.equal(messages.orbitString, 'Error: dx: expected a number, got a string');
    assert.equal(messages.orbitMissing, 'Error: dy: expected a number, got undefined');
    assert.equal(messages.zoomNaN, 'Error: factor: not a finite number');
    assert.equal(messages.resizeBool, 'Error: width: expected a number, got a boolean');
    assert.equal(messages.fitString, 'Error: fill: expected a number, got a string');
    assert.equal(messages.fitNone, 'accepted');
    assert.equal(messages.fitTopString, 'Error: top: expected a number, got a string');
    assert.equal(messages.fitTopNegative, 'Error: fit.top: must be ≥ 0');
    assert.equal(messages.fitTop, 'accepted');
    assert.equal(messages.rayAtArray, 'Error: x: expected a number, got an array');
    assert.equal(messages.drawWorldPlain, 'Error: world: expected a World, got an object');
    assert.equal(messages.drawWorldFreed, 'Error: world: this World has been freed');
    assert.equal(messages.drawWorldLive, 'accepted');
    assert.match(messages.jointsGetter, /^Error: q(\.length)?: could not be read \(boom\)$/);
    assert.match(messages.displayProxy, /^Error: display: could not be read \(trap\)$/);
    assert.equal(messages.renderAfter, 'accepted');
    assert.equal(messages.renderFreed, 'Error: this Viewer has been freed');
    assert.equal(messages.backendFreed, 'Error: this Viewer has been freed');
    assert.equal(messages.secondFree, 'accepted');
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
  }
});

test(`a hostile caller of every Viewer method gets only Errors naming a field (seed ${SEED}, ${CALLS} calls)`, async () => {
  const browser = await launch({ webgpu: false });
  try {
    const page = await browser.context.newPage();
    const errors = collectErrors(page);
    await page.goto(`${baseUrl}gallery.html?backend=webgl2&small=1`);
    await page.evaluate(() => window.galleryReady);
    const report = await page.evaluate(async ({ seed, calls }) => {
      const sa = await import('./pkg/skeleton_avoidance.js');
      const v = window.gallery.viewer;
      let a = seed >>> 0;
      const next = () => {
        a = (a + 0x6d2b79f5) >>> 0;
        let t = a;
        t = Math.imul(t ^ (t >>> 15), t | 1);
        t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
        return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
      };
      const pick = (xs) => xs[Math.floor(next() * xs.length)];
      const thrower = () => { throw new Error('getter'); };
      const world = new sa.World(sa.exampleScenario('planar-transition'));
      const HOSTILE = [
        undefined, null, true, 0, -0, 1, -1, 0.5, NaN, Infinity, -Infinity, 1e308, -1e308, 5e-324, 2 ** 32, '1', '', 'top', 'planar3',
        Symbol('s'), 10n, () => 1, [], [0, 0, 0], [1e308, 0, 0], [NaN, 0, 0], new Float64Array(3), { preset: 'lwr4' }, { preset: 'nope' },
        { volumes: true }, { volumes: 1 }, { get x() { return thrower(); } }, new Proxy({}, { ownKeys: thrower, get: thrower }),
        JSON.parse('{"__proto__": {"x": 1}}'), world, new Array(200001).fill(0), [[[[[[[[0]]]]]]]],
      ];
      const hostile = () => pick(HOSTILE);
      // Valid arguments to mix in, so that accepted calls happen too.
      const valid = {
        setRobot: () => [pick([{ preset: 'planar3' }, 'lwr4'])], setJoints: () => [[0.1, 0.2, 0.3]], setView: () => [pick(['3d', 'top', 'auto'])],
        setSelected: () => [pick(['box', null])], projectPoint: () => [[0, 0, 0]], setDisplay: () => [{ volumes: true, nodes: false }],
        orbit: () => [0.1, -0.1], pan: () => [3, 4], zoom: () => [1.1], fit: () => [0.75, 30], resize: () => [200, 150], rayAt: () => [10, 20],
        drawWorld: () => [world], drawState: () => [world.state()], render: () => [], state: () => [], viewDirection: () => [],
      };
      const names = Object.keys(valid);
      const stats = { calls: 0, accepted: 0, refused: 0 };
      const failures = [];
      const namesField = /^([A-Za-z_$][\w$]*|\[\d+\])([.\w$[\]-]*): \S/;
      for (let k = 0; k < calls && failures.length < 10; k++) {
        const name = pick(names);
        const args = valid[name]().map((x) => (next() < 0.4 ? hostile() : x));
        if (next() < 0.1) args.push(hostile());
        stats.calls++;
        try {
          v[name](...args);
          stats.accepted++;
        } catch (e) {
          stats.refused++;
          if (!(e instanceof Error) || e.constructor !== Error) failures.push(`${name}: threw ${e?.constructor?.name}: ${e?.message ?? e}`);
          else if (!namesField.test(e.message)) failures.push(`${name}: message names no field: ${e.message}`);
        }
        try {
          v.render();
        } catch (e) {
          failures.push(`after ${name}: render() throws ${e?.constructor?.name}: ${e?.message}`);
        }
      }
      world.free();
      return { stats, failures };
    }, { seed: SEED, calls: CALLS });
    console.log(`# Viewer fuzz: ${report.stats.calls} calls, ${report.stats.accepted} accepted, ${report.stats.refused} refused with an Error, ${report.failures.length} failures`);
    assert.deepEqual(report.failures, []);
    assert.ok(report.stats.accepted > 0 && report.stats.refused > 0);
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
  }
});
