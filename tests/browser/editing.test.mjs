// The playground's editing, export and keyboard (issue 11), with real input:
// the DH table and joint limits refuse bad values in place; every preset
// (dual-arm's 15 joints) loads from the panel; the trace downloads as CSV and
// JSON; buttons and the obstacle list work from the keyboard; Share leaves
// the address bar alone.
//
// Screenshots go to tests/artifacts/ (git-ignored): look at them.
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

const state = (page) => page.evaluate(() => window.playground.state());

async function open(page, query = '') {
  await page.goto(`${baseUrl}${query}`);
  await page.evaluate(() => window.playground.ready);
  await frames(page, 3);
}

async function download(page, selector) {
  const [file] = await Promise.all([page.waitForEvent('download'), page.locator(selector).click()]);
  return fs.readFileSync(await file.path(), 'utf8');
}

test('the DH table refuses bad values in place, shows the joint limits, and every preset loads', async () => {
  const browser = await launch({ webgpu: true, viewport: { width: 1280, height: 800 } });
  try {
    const page = await browser.context.newPage();
    const errors = collectErrors(page);
    await open(page, '?scenario=planar-transition&paused');
    const cell = page.locator('#dh-0-a');
    const message = page.locator('#dh-message');
    for (const [text, reason] of [['1e6', /outside \[-10, 10\] m/], ['0x10', /not a decimal number/], ['abc', /not a decimal number/], ['', /is empty/]]) {
      await cell.fill(text);
      assert.match(await message.innerText(), reason, `"${text}"`);
      assert.equal(await cell.getAttribute('aria-invalid'), 'true');
      await page.locator('#apply-dh').click();
      assert.equal((await state(page)).world.skeleton.nodes.length > 0, true);
    }
    await cell.fill('0.45');
    assert.equal(await message.innerText(), '');
    // A joint limit out of order is refused too; a good one is applied.
    await page.locator('#lim-0-maxVelocity').fill('-1');
    assert.match(await message.innerText(), /v max/);
    await page.locator('#lim-0-maxVelocity').fill('1.5');
    await page.locator('#apply-dh').click();
    await frames(page, 2);
    const spec = await page.evaluate(() => window.playground.app.robotSpec);
    assert.equal(spec.joints[0].a, 0.45);
    assert.equal(spec.joints[0].maxVelocity, 1.5);
    await page.locator('#dh-table').screenshot({ path: path.join(artifacts, 'dh-table.png') });
    // dual-arm from the preset menu: 15 joints, 15 sliders, 15 rows.
    await page.locator('#preset').selectOption('dual-arm');
    await frames(page, 3);
    assert.equal((await state(page)).q.length, 15, 'dual-arm has 15 joints');
    assert.equal(await page.locator('#joints input[type=range]').count(), 15);
    assert.equal(await page.locator('#dh-table tbody tr').count(), 15);
    assert.ok(await page.locator('#error').isHidden(), 'no error');
    for (const preset of ['lwr4', 'panda', 'ur5', 'planar3']) {
      await page.locator('#preset').selectOption(preset);
      await frames(page, 2);
      assert.ok(await page.locator('#error').isHidden(), `${preset}: no error`);
      assert.equal(await page.locator('#dh-message').innerText(), '', `${preset}: no message`);
    }
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
  }
});

test('the trace downloads as CSV (one row per sample, header only when empty) and JSON', async () => {
  const browser = await launch({ webgpu: true, viewport: { width: 1280, height: 800 } });
  try {
    const page = await browser.context.newPage();
    const errors = collectErrors(page);
    await open(page, '?scenario=planar-transition&paused');
    const empty = (await download(page, '#export-csv')).trim().split('\n');
    assert.equal(empty.length, 1, 'header only');
    assert.match(empty[0], /^t,q1,q2,q3,qdot1,qdot2,qdot3,min_clearance,/);
    await page.locator('#run').click();
    await page.waitForFunction(() => window.playground.state().world.t > 0.6, null, { timeout: 20000 });
    await page.locator('#run').click();
    const rows = (await download(page, '#export-csv')).trim().split('\n');
    const samples = await page.evaluate(() => window.playground.app.trace.samples.length);
    assert.equal(rows.length, samples + 1, 'one row per sample');
    const header = rows[0].split(',');
    for (const row of rows.slice(1)) assert.equal(row.split(',').length, header.length);
    const last = rows.at(-1).split(',');
    assert.ok(Math.abs(Number(last[0]) - (await state(page)).world.t) < 1e-9, 'the last row is now');
    assert.ok(rows.some((r) => /transitionStart/.test(r)), 'events in their rows');
    const json = JSON.parse(await download(page, '#export-json'));
    assert.equal(json.samples.length, samples);
    assert.deepEqual(json.joints, ['1', '2', '3']);
    assert.ok(json.events.some((e) => e.kind === 'transitionStart'));
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
  }
});

test('keyboard: Space presses a focused button, the obstacle list is reachable, the view shows focus; Share leaves the address bar', async () => {
  const browser = await launch({ webgpu: true, viewport: { width: 1280, height: 800 } });
  try {
    const page = await browser.context.newPage();
    const errors = collectErrors(page);
    await open(page, '?scenario=lwr4-elbow');
    // Space on the focused help button opens the help and does not pause.
    await page.locator('#help-button').focus();
    await page.keyboard.press(' ');
    assert.ok(await page.locator('#help').isVisible(), 'the help opened');
    assert.equal((await state(page)).running, true, 'still running');
    await page.keyboard.press('Escape');
    // The obstacle list: Tab reaches its entries, Enter selects.
    const item = page.locator('#obstacle-list li').first();
    await item.focus();
    await page.keyboard.press('Enter');
    const id = (await state(page)).selected;
    assert.ok(id, 'Enter selected an obstacle');
    // The view: focused by Tab, it shows an outline; Space there pauses.
    await page.locator('#view').focus();
    await page.keyboard.press(' ');
    assert.equal((await state(page)).running, false, 'Space in the view pauses');
    const outline = await page.locator('#view').evaluate((el) => getComputedStyle(el).outlineStyle);
    assert.notEqual(outline, 'none', 'visible focus');
    await page.keyboard.press('f');
    // Share: the link is offered, the address bar keeps no scene.
    const url = await page.evaluate(() => window.playground.app.share());
    assert.match(url, /#scenario=/);
    assert.equal(await page.evaluate(() => location.hash), '');
    assert.equal(await page.locator('#share-link').inputValue(), url);
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
  }
});
