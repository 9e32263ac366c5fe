// Every obstacle primitive drawn by the renderer (the gallery page), on both
// backends: the canvas is not blank and the selected box is highlighted.
// Screenshots go to tests/artifacts/: look at them.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { serve } from '../../scripts/serve.mjs';
import { launch, collectErrors, repo, artifacts } from './chromium.mjs';
import { decodePng, pixel } from './png.mjs';

let server;
let baseUrl;

before(async () => {
  fs.mkdirSync(artifacts, { recursive: true });
  ({ server, url: baseUrl } = await serve({ port: 0 }));
});
after(() => new Promise((resolve) => server.close(resolve)));

for (const backend of ['webgpu', 'webgl2']) {
  test(`every primitive is drawn (${backend})`, async () => {
    const browser = await launch({ webgpu: true });
    try {
      const page = await browser.context.newPage();
      const errors = collectErrors(page);
      await page.goto(`${baseUrl}gallery.html?backend=${backend}`);
      await page.evaluate(() => window.galleryReady);
      const png = await page.locator('#view').screenshot();
      fs.writeFileSync(path.join(artifacts, `gallery-${backend}.png`), png);
      const img = decodePng(png);
      // The selected box is drawn in the highlight colour (yellow) where it projects.
      const at = await page.evaluate(() => window.gallery.viewer.projectPoint([0.75, 0.0, 0.16]));
      assert.ok(at, 'the box is in front of the camera');
      const [r, g, b] = pixel(img, Math.round(at[0]), Math.round(at[1]));
      assert.ok(r > 180 && g > 120 && b < 110, `box top is highlighted, got ${[r, g, b]}`);
      // The sphere is drawn in the obstacle colour (red-ish), seen through its uncertainty region.
      const s = await page.evaluate(() => window.gallery.viewer.projectPoint([0.15, -0.5, 0.1]));
      const [sr, sg, sb] = pixel(img, Math.round(s[0]), Math.round(s[1]));
      assert.ok(sr > sg + 40 && sr > sb + 40, `sphere is red, got ${[sr, sg, sb]}`);
      assert.deepEqual(errors, []);
    } finally {
      await browser.close();
    }
  });
}
