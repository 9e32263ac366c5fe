// The articulated human in the playground, with real input: dragging a hand
// moves only the arm it belongs to; a recorded keypoint track plays (and a
// bad one is refused, the scene unchanged); the HUD and the clearance
// legend name the closest part. Screenshots at 1280×800 and 390×844 go to
// tests/artifacts/ (git-ignored): look at them.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { serve } from '../../scripts/serve.mjs';
import { launch, collectErrors, frames, artifacts, repo } from './chromium.mjs';

let server;
let baseUrl;

before(async () => {
  fs.mkdirSync(artifacts, { recursive: true });
  ({ server, url: baseUrl } = await serve({ port: 0 }));
});
after(() => new Promise((resolve) => server.close(resolve)));

const PARTS = ['pelvis', 'torso', 'neck', 'head', 'leftUpperArm', 'leftForearm', 'leftHand', 'rightUpperArm', 'rightForearm', 'rightHand',
  'leftThigh', 'leftShin', 'leftFoot', 'rightThigh', 'rightShin', 'rightFoot'];

async function open(page, query) {
  await page.goto(`${baseUrl}${query}`);
  await page.evaluate(() => window.playground.ready);
  await frames(page, 3);
}

const person = (page) => page.evaluate(() => window.playground.app.world.state().obstacles.find((o) => o.id === 'person'));

/** Page coordinates of the middle of part `k` of the person, and whether a pick there names that part. */
async function partOnScreen(page, k) {
  return page.evaluate((k) => {
    const app = window.playground.app;
    const o = app.world.state().obstacles.find((x) => x.id === 'person');
    const c = o.parts[k];
    const p = c.type === 'sphere' ? c.center : c.a.map((v, i) => 0.5 * (v + c.b[i]));
    const [x, y] = app.viewer.projectPoint(p);
    const ray = app.viewer.rayAt(x, y);
    const hit = app.world.pick(ray.origin, ray.direction);
    const r = app.canvas.getBoundingClientRect();
    const dpr = window.devicePixelRatio || 1;
    return { x: r.left + x / dpr, y: r.top + y / dpr, part: hit?.part ?? null, id: hit?.id ?? null };
  }, k);
}

const same = (a, b) => JSON.stringify(a) === JSON.stringify(b);

test('dragging a hand moves only the arm it belongs to; dragging the body moves the person', async () => {
  const browser = await launch({ webgpu: true, viewport: { width: 1280, height: 800 } });
  try {
    const page = await browser.context.newPage();
    const errors = collectErrors(page);
    await open(page, '?scenario=human-reach&paused');
    const before = await person(page);
    assert.equal(before.parts.length, 16);
    // Whichever hand the view shows unhidden.
    let k = PARTS.indexOf('rightHand');
    let at = await partOnScreen(page, k);
    if (at.part !== 'rightHand') {
      k = PARTS.indexOf('leftHand');
      at = await partOnScreen(page, k);
    }
    assert.match(at.part ?? '', /Hand$/, `a pick on a hand names it (got ${at.part})`);
    const side = at.part.startsWith('left') ? 'left' : 'right';
    await page.mouse.move(at.x, at.y);
    await page.mouse.down();
    await page.mouse.move(at.x - 25, at.y - 45, { steps: 6 });
    await page.mouse.up();
    await frames(page, 2);
    const after = await person(page);
    assert.ok(!after.shape.animation, 'the person holds the dragged pose');
    const arm = new Set([`${side}UpperArm`, `${side}Forearm`, `${side}Hand`]);
    PARTS.forEach((name, i) => {
      if (arm.has(name)) return;
      assert.ok(same(after.parts[i], before.parts[i]), `${name} did not move`);
    });
    const tip = (o) => o.parts[k].b;
    const moved = Math.hypot(...[0, 1, 2].map((i) => tip(after)[i] - tip(before)[i]));
    assert.ok(moved > 0.03, `the ${side} hand moved (${moved.toFixed(3)} m)`);
    assert.ok(!same(after.parts[k - 2], before.parts[k - 2]), 'its upper arm turned');
    await page.screenshot({ path: path.join(artifacts, 'human-hand-drag-1280.png') });
    // The body: a drag on the torso moves the whole person (every part).
    const torso = await partOnScreen(page, PARTS.indexOf('torso'));
    if (torso.part === 'torso') {
      const b2 = await person(page);
      await page.mouse.move(torso.x, torso.y);
      await page.mouse.down();
      await page.mouse.move(torso.x + 30, torso.y, { steps: 4 });
      await page.mouse.up();
      await frames(page, 2);
      const a2 = await person(page);
      assert.ok(PARTS.every((_, i) => !same(a2.parts[i], b2.parts[i])), 'every part moved with the body');
    }
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
  }
});

test('a keypoint track plays, a bad one is refused and the scene is unchanged; the closest part is named', async () => {
  const browser = await launch({ webgpu: true, viewport: { width: 1280, height: 800 } });
  try {
    const page = await browser.context.newPage();
    const errors = collectErrors(page);
    await open(page, '?scenario=human-reach&paused');
    await page.evaluate(() => window.playground.app.select('person'));
    await frames(page, 1);
    // A track whose timestamps go back: refused, the person unchanged.
    const shape = (await person(page)).shape;
    const bad = path.join(artifacts, 'bad-track.json');
    const sample = JSON.parse(fs.readFileSync(path.join(repo, 'web', 'tracks', 'reach-coco17.json'), 'utf8'));
    sample.frames[3].t = sample.frames[2].t;
    fs.writeFileSync(bad, JSON.stringify(sample));
    await page.locator('#human-track').setInputFiles(bad);
    await page.locator('#error').waitFor({ state: 'visible' });
    assert.match(await page.locator('#error').innerText(), /frames\[3\]\.t: must increase/);
    assert.ok(same((await person(page)).shape, shape), 'a refused track leaves the person as it was');
    // The shipped sample: replayed by the selected person.
    await page.locator('#human-track').setInputFiles(path.join(repo, 'web', 'tracks', 'reach-coco17.json'));
    await page.waitForFunction(() => window.playground.app.world.state().obstacles.find((o) => o.id === 'person').shape.animation?.keyframes?.length === 75);
    assert.match(await page.locator('#status').innerText(), /coco17, 75 frames/);
    const handAt = async () => (await person(page)).parts[9].b;
    const h0 = await handAt();
    await page.evaluate(() => { const app = window.playground.app; if (!app.running) app.toggleRun(); });
    await page.waitForFunction(() => window.playground.app.world.state().t > 1.5);
    const h1 = await handAt();
    assert.ok(Math.hypot(...[0, 1, 2].map((i) => h1[i] - h0[i])) > 0.2, 'the track moves the hand');
    assert.deepEqual(errors.filter((e) => !/frames\[3\]/.test(e)), []);
  } finally {
    await browser.close();
  }
});

test('a BVH recording plays: the person walks past the arm; a malformed one is refused', async () => {
  const browser = await launch({ webgpu: true, viewport: { width: 1280, height: 800 } });
  try {
    const page = await browser.context.newPage();
    const errors = collectErrors(page);
    await open(page, '?scenario=human-reach&paused');
    await page.evaluate(() => window.playground.app.select('person'));
    await frames(page, 1);
    const shape = (await person(page)).shape;
    const text = fs.readFileSync(path.join(repo, 'web', 'tracks', 'walk-by.bvh'), 'utf8');
    const bad = path.join(artifacts, 'bad-walk.bvh');
    fs.writeFileSync(bad, text.replace(/Frame Time: .*/, 'Frame Time: -0.1'));
    await page.locator('#human-track').setInputFiles(bad);
    await page.locator('#error').waitFor({ state: 'visible' });
    assert.match(await page.locator('#error').innerText(), /Frame Time: must be in \(0, 10\] s/);
    assert.ok(same((await person(page)).shape, shape), 'a refused file leaves the person as it was');
    await page.locator('#human-track').setInputFiles(path.join(repo, 'web', 'tracks', 'walk-by.bvh'));
    await page.waitForFunction(() => window.playground.app.world.state().obstacles.find((o) => o.id === 'person').shape.animation?.keyframes?.length === 90);
    assert.match(await page.locator('#status').innerText(), /bvh, 90 frames/);
    const pelvisAt = async () => (await person(page)).parts[0].a;
    const p0 = await pelvisAt();
    await page.evaluate(() => { const app = window.playground.app; if (!app.running) app.toggleRun(); });
    await page.waitForFunction(() => window.playground.app.world.state().t > 1.5);
    const p1 = await pelvisAt();
    assert.ok(p0[1] - p1[1] > 1.0, `the person walks along −y (${p0[1]} → ${p1[1]})`);
    await frames(page, 2);
    await page.screenshot({ path: path.join(artifacts, 'human-bvh-walk-1280x800.png') });
    // The selected person's JSON (90 keyframes, no spaces) wraps within the panel.
    const json = await page.evaluate(() => {
      const app = window.playground.app;
      const el = app.root.getElementById?.('shape-json') ?? app.root.querySelector('#shape-json');
      return el && { scroll: el.scrollWidth, client: el.clientWidth, length: el.textContent.length };
    });
    assert.ok(json && json.length > 1000 && json.scroll <= json.client, `the shape's JSON overflows: ${JSON.stringify(json)}`);
    assert.deepEqual(errors.filter((e) => !/Frame Time/.test(e)), []);
  } finally {
    await browser.close();
  }
});

for (const [w, hgt] of [[1280, 800], [390, 844]]) {
  test(`a person reaching across the arm at ${w}×${hgt}: the HUD names the closest part`, async () => {
    const browser = await launch({ webgpu: true, viewport: { width: w, height: hgt } });
    try {
      const page = await browser.context.newPage();
      const errors = collectErrors(page);
      await open(page, '?scenario=human-reach');
      // Wait for the state: the closest part is the hand, and the HUD (drawn
      // each frame from the state) says so. Read together, at one moment,
      // since the simulation runs on.
      await page.waitForFunction(() => window.playground.app.world.state().closestPart === 'person:rightHand', null, { timeout: 60_000 });
      const seen = await page.waitForFunction(() => {
        const app = window.playground.app;
        const part = app.world.state().closestPart;
        return part === 'person:rightHand' && app.hud.textContent.includes(part) && app.hud.textContent;
      }, null, { timeout: 60_000 });
      const hud = await seen.jsonValue();
      assert.match(hud, /person:rightHand/);
      await page.screenshot({ path: path.join(artifacts, `human-reach-${w}x${hgt}.png`) });
      assert.deepEqual(errors, []);
    } finally {
      await browser.close();
    }
  });
}
