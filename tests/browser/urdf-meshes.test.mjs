// A URDF with its collision meshes picked as files in the playground (the
// UR5 of crate/tests/data, licences there): the robot loads with its volumes
// fitted and the figures shown, the meshes are drawn (pixels that change when
// the meshes are switched off, on WebGPU and WebGL2), the meshes / volumes
// toggles change the picture, a click on the mesh in Pin mode pins a point of
// the skeleton beneath, and a mesh that is missing is named. 1280×800.
//
// Screenshots go to tests/artifacts/ (git-ignored): look at them.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { serve } from '../../scripts/serve.mjs';
import { launch, collectErrors, frames, artifacts } from './chromium.mjs';
import { pixel, colourDistance } from './png.mjs';
import { data, UR5_PARTS as PARTS, shot, differing, display } from './urdf-kit.mjs';

let server;
let baseUrl;

before(async () => {
  fs.mkdirSync(artifacts, { recursive: true });
  ({ server, url: baseUrl } = await serve({ port: 0 }));
});
after(() => new Promise((resolve) => server.close(resolve)));

const files = (skip = []) => [
  { name: 'ur5_robot.urdf', mimeType: 'application/xml', buffer: fs.readFileSync(data('urdf/ur5_robot.urdf')) },
  ...PARTS.filter((p) => !skip.includes(p)).map((p) => ({ name: `${p}.stl`, mimeType: 'model/stl', buffer: fs.readFileSync(data(`meshes/ur5/collision/${p}.stl`)) })),
];

for (const backend of ['webgpu', 'webgl2']) {
  test(`URDF files with meshes: drawn, toggled, picked on the mesh (${backend})`, async () => {
    const browser = await launch({ webgpu: backend === 'webgpu', viewport: { width: 1280, height: 800 } });
    try {
      const page = await browser.context.newPage();
      const errors = collectErrors(page);
      await page.goto(`${baseUrl}?scenario=lwr4-elbow&paused&backend=${backend}`);
      await page.evaluate(() => window.playground.ready);
      assert.equal((await page.evaluate(() => window.playground.state())).backend, backend);
      await page.locator('#urdf-files').setInputFiles(files());
      await page.locator('#status').filter({ hasText: /Volumes fitted to 6 collision meshes/ }).waitFor({ timeout: 30000 });
      const status = await page.locator('#status').innerText();
      assert.match(status, /vertices inside [\d.]+ % → 100\.0 %/);
      const both = await shot(page, `urdf-ur5-both-${backend}.png`);
      await display(page, { meshes: true, volumes: false });
      const meshesOnly = await shot(page, `urdf-ur5-meshes-${backend}.png`);
      await display(page, { meshes: false, volumes: false });
      const neither = await shot(page, `urdf-ur5-neither-${backend}.png`);
      await display(page, { meshes: false, volumes: true });
      const volumesOnly = await shot(page, `urdf-ur5-volumes-${backend}.png`);
      const meshPixels = differing(meshesOnly, neither);
      assert.ok(meshPixels > 2000, `mesh pixels: ${meshPixels}`);
      assert.ok(differing(meshesOnly, volumesOnly) > 1000, 'meshes and volumes differ');
      assert.ok(differing(both, meshesOnly) > 1000, 'the volumes show over the meshes');

      // Pin mode, a click on the upper arm's mesh: a point of the skeleton
      // beneath it is pinned (the fitted volumes hold the mesh).
      await display(page, { meshes: true, volumes: false });
      await frames(page, 3);
      const target = await page.evaluate(() => {
        const app = window.playground.app;
        const s = app.world.state();
        const seg = s.skeleton.segments.filter((x) => x.link === 2).sort((a, b) => b.radius[0] - a.radius[0])[0];
        const a = s.skeleton.nodes[seg.from];
        const b = s.skeleton.nodes[seg.to];
        const p = a.map((v, i) => 0.5 * (v + b[i]));
        const [x, y] = app.viewer.projectPoint(p);
        const r = app.canvas.getBoundingClientRect();
        return { x: r.left + x, y: r.top + y, cx: x, cy: y };
      });
      const under = pixel(meshesOnly, Math.round(target.cx), Math.round(target.cy));
      const bare = pixel(neither, Math.round(target.cx), Math.round(target.cy));
      assert.ok(colourDistance(under, bare) > 30, `a mesh pixel under the click: ${under} vs ${bare}`);
      await page.locator('#pin-mode').click();
      await page.mouse.click(target.x, target.y);
      await frames(page, 2);
      const pinned = await page.evaluate(() => window.playground.app.scenario.controller?.pinned ?? []);
      assert.equal(pinned.length, 1, 'one point pinned');
      assert.ok([2, 3].includes(pinned[0].link), `pinned on link ${pinned[0].link}`);
      assert.deepEqual(errors, []);
    } finally {
      await browser.close();
    }
  });
}

test('a missing mesh is named, the robot still loads', async () => {
  const browser = await launch({ webgpu: false, viewport: { width: 1280, height: 800 } });
  try {
    const page = await browser.context.newPage();
    await page.goto(`${baseUrl}?scenario=lwr4-elbow&paused&backend=webgl2`);
    await page.evaluate(() => window.playground.ready);
    await page.locator('#urdf-files').setInputFiles(files(['forearm']));
    await page.locator('#status').filter({ hasText: /Loaded URDF/ }).waitFor({ timeout: 30000 });
    const message = await page.locator('#error').innerText();
    assert.match(message, /forearm\.stl/);
    assert.equal((await page.evaluate(() => window.playground.app.robotSpec.joints.length)), 6);
    await page.screenshot({ path: path.join(artifacts, 'urdf-ur5-missing-mesh.png') });
  } finally {
    await browser.close();
  }
});
