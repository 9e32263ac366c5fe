// Pinning a control point by clicking the skeleton, with real mouse and
// keyboard input: Pin mode, a click on a link, the point in the list and the
// selection `pinned`, the control point where its DH values put it, points
// typed as DH values (bad ones refused in place, nothing changed), removal
// by button and by keyboard, and the points carried by Share, Save and
// Open. At 1280×800 and 390×844 (the panel as a drawer).
//
// Screenshots go to tests/artifacts/ (git-ignored): look at them.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
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

/** DH values and positions agree to this (m). */
const EXACT = 1e-9;

const state = (page) => page.evaluate(() => window.playground.state());
const controller = (page) => page.evaluate(() => window.playground.app.scenario.controller);
const dist = (p, q) => Math.hypot(...p.map((x, i) => x - q[i]));

async function open(page, query) {
  await page.goto(`${baseUrl}${query}`);
  await page.evaluate(() => window.playground.ready);
  await frames(page, 3);
}

/**
 * Page coordinates of the point at fraction `t` of the longest segment of
 * link `link` (its spine), and that point.
 */
async function linkOnScreen(page, link, t = 0.5) {
  return page.evaluate(({ link, t }) => {
    const app = window.playground.app;
    const s = app.world.state();
    const segs = s.skeleton.segments.filter((x) => x.link === link);
    const length = (x) => Math.hypot(...[0, 1, 2].map((i) => s.skeleton.nodes[x.to][i] - s.skeleton.nodes[x.from][i]));
    const seg = segs.sort((x, y) => length(y) - length(x))[0];
    const a = s.skeleton.nodes[seg.from];
    const b = s.skeleton.nodes[seg.to];
    const p = a.map((v, i) => v + t * (b[i] - a[i]));
    const [x, y] = app.viewer.projectPoint(p);
    const r = app.canvas.getBoundingClientRect();
    const dpr = window.devicePixelRatio || 1;
    return { x: r.left + x / dpr, y: r.top + y / dpr, point: p };
  }, { link, t });
}

/** Where DH values put a point at joints `q` (the library's controlPoint). */
const dhPosition = (page, q, dh) => page.evaluate(({ q, dh }) => {
  const app = window.playground.app;
  return app.wasm.controlPoint(app.robotSpec, q, dh).position;
}, { q, dh });

test('a click on a link pins a control point that follows its DH values; typed, removed, shared, saved and opened', async () => {
  const browser = await launch({ webgpu: true, viewport: { width: 1280, height: 800 } });
  try {
    const page = await browser.context.newPage();
    const errors = collectErrors(page);
    await open(page, '?scenario=lwr4-elbow&paused');
    const before = await controller(page);
    assert.notEqual(before.selection, 'pinned');
    assert.ok(await page.locator('#pinned-empty').isVisible(), 'the empty list says how to pin');

    // Pin mode with the button, then a click on link 5 (the forearm).
    await page.locator('#pin-mode').click();
    assert.equal(await page.locator('#pin-mode').getAttribute('aria-pressed'), 'true');
    const target = await linkOnScreen(page, 5, 0.6);
    await page.mouse.click(target.x, target.y);
    await frames(page, 2);
    const items = page.locator('#pinned-list li');
    assert.equal(await items.count(), 1, 'one pinned point listed');
    assert.match(await items.first().innerText(), /link 5 · d′ [\d.]+ · a′ [\d.]+ m/);
    assert.equal(await page.locator('#selection').inputValue(), 'pinned');
    const c1 = await controller(page);
    assert.equal(c1.selection, 'pinned');
    assert.equal(c1.pinned.length, 1);
    const dh = c1.pinned[0];
    assert.equal(dh.link, 5);
    // The pinned point is the one clicked: on the spine, under the pointer.
    const s0 = await state(page);
    const at = await dhPosition(page, s0.q, dh);
    assert.ok(dist(at, target.point) < 0.01, `pinned ${JSON.stringify(at)} vs clicked ${JSON.stringify(target.point)}`);
    const back = await page.evaluate((p) => window.playground.app.viewer.projectPoint(p), at);
    const box = await page.locator('#view').boundingBox();
    assert.ok(Math.hypot(box.x + back[0] - target.x, box.y + back[1] - target.y) < 3, 'projects back under the pointer');

    // One control step: the control point is the pinned one, where its DH
    // values put it in the configuration the step started from.
    await page.locator('#step').click();
    await page.waitForFunction(() => window.playground.state().world.controlPoints.length > 0, null, { timeout: 10000 });
    const s1 = await state(page);
    const cp = s1.world.controlPoints[0];
    assert.equal(s1.world.controlPoints.length, 1);
    assert.deepEqual([cp.link, cp.d, cp.a], [dh.link, dh.d, dh.a]);
    assert.ok(dist(cp.position, await dhPosition(page, s0.q, dh)) < EXACT, 'the control point sits at its DH values');
    // Running, it follows the arm.
    await page.locator('#run').click();
    await page.waitForFunction(() => window.playground.state().world.t > 0.3, null, { timeout: 20000 });
    await page.locator('#run').click();
    await page.locator('#step').click();
    await frames(page, 2);
    const s2 = await state(page);
    const cp2 = s2.world.controlPoints[0];
    assert.deepEqual([cp2.link, cp2.d, cp2.a], [dh.link, dh.d, dh.a]);
    assert.ok(dist(cp2.position, await dhPosition(page, s2.q, dh)) < 0.01, 'still on link 5 (within one step of motion)');
    await page.screenshot({ path: path.join(artifacts, 'pin-1280x800.png') });

    // Typed DH values: refused in place (nothing changes), then accepted.
    await page.locator('#pin-mode').click();
    assert.equal(await page.locator('#pin-mode').getAttribute('aria-pressed'), 'false');
    await page.locator('#pin-link').selectOption('3');
    for (const [d, reason] of [['0x10', /not a decimal number/], ['5', /pinned\[1\]\.d: 5 is outside the link's reach/]]) {
      await page.locator('#pin-d').fill(d);
      await page.locator('#pin-add').click();
      assert.match(await page.locator('#pin-message').innerText(), reason, d);
      assert.equal(await items.count(), 1, `${d}: nothing added`);
      assert.deepEqual(await controller(page), c1, `${d}: the controller is unchanged`);
    }
    await page.locator('#pin-d').fill('0.2');
    await page.locator('#pin-add').click();
    assert.equal(await page.locator('#pin-message').innerText(), '');
    assert.equal(await items.count(), 2);
    assert.deepEqual((await controller(page)).pinned[1], { link: 3, d: 0.2, a: 0 });

    // Share, Save and Open carry the points.
    const url = await page.evaluate(() => window.playground.app.shareUrl());
    const [file] = await Promise.all([page.waitForEvent('download'), page.locator('#save').click()]);
    const saved = JSON.parse(fs.readFileSync(await file.path(), 'utf8'));
    assert.deepEqual(saved.controller.pinned, (await controller(page)).pinned);
    assert.equal(saved.controller.selection, 'pinned');
    const shared = await browser.context.newPage();
    await open(shared, url.slice(baseUrl.length));
    assert.equal(await shared.locator('#pinned-list li').count(), 2, 'the shared link restores the points');
    assert.equal(await shared.locator('#selection').inputValue(), 'pinned');
    await shared.close();

    // Removal: the button, then the keyboard (Delete on a focused entry).
    await items.nth(1).locator('button').click();
    assert.equal(await items.count(), 1);
    await items.first().focus();
    await page.keyboard.press('Delete');
    assert.equal(await items.count(), 0, 'removed by keyboard');
    const after = await controller(page);
    assert.deepEqual(after.pinned, []);
    assert.equal(after.selection, before.selection, 'back to the selection used before');
    assert.equal(await page.locator('#selection').inputValue(), before.selection);
    assert.equal(await page.evaluate(() => window.playground.app.world.state().obstacles.length > 0), true, 'Delete removed no obstacle');

    // Open… the saved file: the points come back.
    const tmp = path.join(fs.mkdtempSync(path.join(os.tmpdir(), 'pin-')), 'pinned.json');
    fs.writeFileSync(tmp, JSON.stringify(saved));
    await page.locator('#file').setInputFiles(tmp);
    await page.waitForFunction(() => window.playground.app.scenario.controller.pinned?.length === 2, null, { timeout: 10000 });
    assert.equal(await items.count(), 2, 'Open… restores the points');
    fs.rmSync(path.dirname(tmp), { recursive: true, force: true });

    // A new robot starts without the old robot's points.
    await page.locator('#preset').selectOption('ur5');
    await frames(page, 2);
    assert.ok(await page.locator('#error').isHidden(), 'ur5 loads');
    assert.equal(await items.count(), 0);
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
  }
});

test('on a phone: the P key or the drawer\'s Pin button, a tap on the planar arm, the list in the drawer', async () => {
  const browser = await launch({ webgpu: false, viewport: { width: 390, height: 844 } });
  try {
    const page = await browser.context.newPage();
    const errors = collectErrors(page);
    await open(page, '?scenario=planar-transition&paused&backend=webgl2');
    // P in the focused view turns Pin mode on; a click off the arm pins nothing.
    await page.locator('#view').focus();
    await page.keyboard.press('p');
    assert.equal(await page.locator('#pin-mode').getAttribute('aria-pressed'), 'true');
    const box = await page.locator('#view').boundingBox();
    await page.mouse.click(box.x + 8, box.y + box.height - 8);
    assert.equal(await page.locator('#pinned-list li').count(), 0, 'nothing under the pointer, nothing pinned');
    const target = await linkOnScreen(page, 2, 0.5);
    await page.mouse.click(target.x, target.y);
    await frames(page, 2);
    const c = await controller(page);
    assert.equal(c.selection, 'pinned');
    assert.equal(c.pinned.length, 1);
    assert.equal(c.pinned[0].link, 2);
    // planar3 link 2 is 0.3 m long, along its a: the middle is a′ ≈ 0.15.
    assert.ok(Math.abs(c.pinned[0].a - 0.15) < 0.01 && Math.abs(c.pinned[0].d) < EXACT, JSON.stringify(c.pinned[0]));
    await page.keyboard.press('Escape');
    assert.equal(await page.locator('#pin-mode').getAttribute('aria-pressed'), 'false', 'Escape leaves Pin mode');
    await page.locator('#step').evaluate((b) => b.click());
    await page.waitForFunction(() => window.playground.state().world.controlPoints.length > 0, null, { timeout: 10000 });
    await page.screenshot({ path: path.join(artifacts, 'pin-390x844.png') });
    // The drawer's Pin button closes the drawer, so the arm can be tapped.
    await page.locator('#panel-toggle').click();
    await page.locator('#pin-mode').click();
    assert.equal(await page.locator('#panel-toggle').getAttribute('aria-expanded'), 'false', 'the drawer closed');
    const first = await linkOnScreen(page, 1, 0.3);
    await page.mouse.click(first.x, first.y);
    await frames(page, 2);
    assert.deepEqual((await controller(page)).pinned.map((p) => p.link), [2, 1]);
    await page.locator('#panel-toggle').click();
    await page.locator('#pinned-list').scrollIntoViewIfNeeded();
    assert.ok(await page.locator('#pinned-list li').first().isVisible());
    await page.screenshot({ path: path.join(artifacts, 'pin-390x844-drawer.png') });
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
  }
});
