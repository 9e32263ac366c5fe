// The presets drawn with their manufacturers' collision meshes (iiwa 14, Panda, UR5;
// files and licences in crate/tests/data, served at robots/): picking the
// preset fetches them once and draws them on the preset's own skeleton
// (pixels that go when the meshes are switched off), the meshes follow the
// joints (the world drawn after a step moves them with the arm), a preset
// without meshes draws none, and a folder that cannot be read leaves the
// volumes with a line in the status. 1280×800 and a phone (390×844), WebGPU
// and WebGL2.
//
// Screenshots go to tests/artifacts/ (git-ignored): look at them.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { serve } from '../../scripts/serve.mjs';
import { launch, collectErrors, artifacts } from './chromium.mjs';
import { pixel, colourDistance } from './png.mjs';
import { shot, differing } from './urdf-kit.mjs';

let server;
let baseUrl;

before(async () => {
  fs.mkdirSync(artifacts, { recursive: true });
  ({ server, url: baseUrl } = await serve({ port: 0 }));
});
after(() => new Promise((resolve) => server.close(resolve)));

/** Sets the meshes / volumes toggles (also when the panel is a closed drawer). */
const toggles = (page, meshes, volumes) => page.evaluate(([m, v]) => {
  const app = window.playground.app;
  for (const [id, on] of [['show-meshes', m], ['show-volumes', v]]) {
    (app.root.getElementById?.(id) ?? app.root.querySelector(`#${id}`)).checked = on;
  }
  app.applyDisplay();
  app.edited = true;
}, [meshes, volumes]);

/** Waits until the viewer draws meshes of the preset `name` (the mixin records it). */
const meshesShown = (page, name) => page.waitForFunction((name) => window.playground.app.presetMeshesShown === name, name, { timeout: 60000 });

for (const [backend, viewport] of [['webgpu', { width: 1280, height: 800 }], ['webgl2', { width: 390, height: 844 }]]) {
  test(`the iiwa 14, Panda and UR5 presets with their meshes (${backend}, ${viewport.width}×${viewport.height})`, async () => {
    const browser = await launch({ webgpu: backend === 'webgpu', viewport });
    try {
      const page = await browser.context.newPage();
      const errors = collectErrors(page);
      const fetched = [];
      page.on('request', (r) => { if (r.url().includes('/robots/')) fetched.push(new URL(r.url()).pathname); });
      await page.goto(`${baseUrl}?scenario=lwr4-elbow&paused&backend=${backend}`);
      await page.evaluate(() => window.playground.ready);
      assert.deepEqual(fetched, [], 'nothing fetched for the LWR4');
      for (const name of ['iiwa14', 'panda', 'ur5']) {
        await page.evaluate((name) => window.playground.app.setPreset(name), name);
        await meshesShown(page, name);
        await toggles(page, true, false);
        const meshes = await shot(page, `preset-${name}-${backend}-meshes.png`);
        await toggles(page, false, false);
        const neither = await shot(page, `preset-${name}-${backend}-neither.png`);
        await toggles(page, true, true);
        const n = differing(meshes, neither);
        assert.ok(n > 1500, `${name}: mesh pixels ${n}`);
        await shot(page, `preset-${name}-${backend}.png`);
      }
      const count = fetched.length;
      assert.equal(count, 3 + 8 + 9 + 7, `the URDFs and meshes fetched once: ${fetched.join(' ')}`);
      // The Panda again: from memory.
      await page.evaluate(() => window.playground.app.setPreset('panda'));
      await meshesShown(page, 'panda');
      assert.equal(fetched.length, count, 'fetched once');
      // A preset without meshes: none drawn (switching them off changes nothing).
      await page.evaluate(() => window.playground.app.setPreset('lwr4'));
      await shot(page, `preset-lwr4-${backend}.png`);
      const lwr4 = await page.evaluate(() => window.playground.state().triangles);
      await toggles(page, false, true);
      await shot(page, `preset-lwr4-${backend}-bare.png`);
      assert.equal(await page.evaluate(() => window.playground.state().triangles), lwr4, 'no mesh triangles for the LWR4');
      assert.deepEqual(errors, []);
    } finally {
      await browser.close();
    }
  });
}

test('the meshes follow the joints; a folder that cannot be read leaves the volumes', async () => {
  const browser = await launch({ webgpu: false, viewport: { width: 1280, height: 800 } });
  try {
    const page = await browser.context.newPage();
    await page.goto(`${baseUrl}?scenario=human-panda&paused&backend=webgl2`);
    await page.evaluate(() => window.playground.ready);
    await meshesShown(page, 'panda');
    const q0 = await page.evaluate(() => window.playground.state().q);
    // Run until the arm has moved, then pause: the meshes went with it —
    // a mesh pixel over the middle of the forearm's spine where it is now.
    await page.evaluate(() => window.playground.app.toggleRun());
    await page.waitForFunction(() => window.playground.state().world.t > 1.5, null, { timeout: 60000 });
    await page.evaluate(() => window.playground.app.toggleRun());
    const q = await page.evaluate(() => window.playground.state().q);
    assert.ok(Math.max(...q.map((x, i) => Math.abs(x - q0[i]))) > 0.1, `the arm moved: ${q0} → ${q}`);
    await toggles(page, true, false);
    const moved = await shot(page, 'preset-human-panda-moved.png');
    await toggles(page, false, false);
    const bare = await shot(page, 'preset-human-panda-moved-bare.png');
    const at = await page.evaluate(() => {
      const app = window.playground.app;
      const s = app.world.state();
      const seg = s.skeleton.segments.filter((x) => x.link === 5).sort((a, b) => {
        const len = (x) => Math.hypot(...[0, 1, 2].map((i) => s.skeleton.nodes[x.to][i] - s.skeleton.nodes[x.from][i]));
        return len(b) - len(a);
      })[0];
      const p = s.skeleton.nodes[seg.from].map((v, i) => 0.5 * (v + s.skeleton.nodes[seg.to][i]));
      return app.viewer.projectPoint(p).map(Math.round);
    });
    const [under, none] = [pixel(moved, at[0], at[1]), pixel(bare, at[0], at[1])];
    assert.ok(colourDistance(under, none) > 30, `a mesh pixel over the forearm at ${at}: ${under} vs ${none}`);
    // The whole arm's meshes, not a speck: 1 406 pixels with the camera
    // framing the person whole (the arm about a fifth of the view's height).
    const meshPixels = differing(moved, bare);
    assert.ok(meshPixels > 1000, `the meshes are drawn: ${meshPixels} pixels change without them`);

    // A folder that cannot be read: the status says so, the volumes stay.
    await page.route('**/robots/**', (route) => route.fulfill({ status: 404, body: 'gone' }));
    await page.evaluate(() => { const app = window.playground.app; app.presetFiles = {}; app.setPreset('ur5'); });
    await page.locator('#status').filter({ hasText: /The ur5 meshes could not be drawn: urdf\/ur5_robot\.urdf: HTTP 404/ }).waitFor({ timeout: 30000 });
    assert.equal(await page.evaluate(() => window.playground.app.robotSpec.joints.length), 6);
  } finally {
    await browser.close();
  }
});
