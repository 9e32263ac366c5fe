// Links and files from people, fuzzed: the playground is given seeded
// hostile `#scenario=` links and *Open…* files (malformed base64, cut short,
// huge, wrong types, unknown keys, prototype keys, deep nesting, bad UTF-8)
// and must show a clear message each time, keep the scene and keep running,
// with no uncaught error, no console error and no prototype pollution. A good
// link afterwards still loads.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { serve } from '../../scripts/serve.mjs';
import { encodeShare } from '../../web/scenario-io.js';
import { rng } from '../fuzz/values.mjs';
import { launch, collectErrors, frames } from './chromium.mjs';

let server;
let baseUrl;

before(async () => {
  ({ server, url: baseUrl } = await serve({ port: 0 }));
});
after(() => new Promise((resolve) => server.close(resolve)));

const SEED = Number(process.env.FUZZ_SEED ?? 13);

const GOOD = {
  robot: { preset: 'planar3' },
  q0: [0.3, 0.5, 0.4],
  obstacles: [{ id: 'ball', shape: { type: 'sphere', center: [0.3, -0.55, 0], radius: 0.05 } }],
  dt: 0.001,
  duration: 60,
};

const base64url = (bytes) => Buffer.from(bytes).toString('base64').replaceAll('+', '-').replaceAll('/', '_').replace(/=+$/, '');
const linkOf = (text) => `scenario=${base64url(Buffer.from(text, 'utf8'))}`;
const deep = (n, leaf = '0') => '['.repeat(n) + leaf + ']'.repeat(n);

/** Scenario texts that must be refused, each with what it tries. */
function badTexts(r) {
  const good = JSON.stringify(GOOD);
  const texts = [
    ['empty', ''],
    ['not JSON', 'robot: planar3'],
    ['cut short (1)', good.slice(0, 1 + r.int(good.length - 2))],
    ['cut short (2)', good.slice(0, 1 + r.int(good.length - 2))],
    ['cut short (3)', good.slice(0, 1 + r.int(good.length - 2))],
    ['a number', '5'],
    ['a string', '"planar-transition"'],
    ['null', 'null'],
    ['an array', '[1, 2, 3]'],
    ['robot of the wrong type', JSON.stringify({ ...GOOD, robot: 5 })],
    ['dt as a string', JSON.stringify({ ...GOOD, dt: '0.001' })],
    ['obstacles as an object', JSON.stringify({ ...GOOD, obstacles: { ball: GOOD.obstacles[0] } })],
    ['an unknown key', JSON.stringify({ ...GOOD, colour: 'red' })],
    ['an unknown key in an obstacle', JSON.stringify({ ...GOOD, obstacles: [{ ...GOOD.obstacles[0], mass: 1 }] })],
    ['a __proto__ key', `{"__proto__": {"polluted": 1}, ${good.slice(1)}`],
    ['a nested __proto__ key', good.replace('"radius":0.05', '"radius":0.05,"__proto__":{"polluted":1}')],
    ['constructor.prototype', JSON.stringify({ ...GOOD, constructor: { prototype: { polluted: 1 } } })],
    ['deep nesting (1000 levels)', JSON.stringify({ ...GOOD, q0: 'X' }).replace('"X"', deep(1000))],
    ['deep nesting (100000 levels)', deep(100000)],
    ['a huge array', JSON.stringify({ ...GOOD, q0: new Array(100001).fill(0) })],
    ['a huge number', JSON.stringify(GOOD).replace('"radius":0.05', '"radius":1e400')],
    ['a point of two numbers', JSON.stringify(GOOD).replace('[0.3,-0.55,0]', '[0.3,-0.55]')],
    ['a motion with an empty waypoint', JSON.stringify({ ...GOOD, obstacles: [{ ...GOOD.obstacles[0], motion: { type: 'waypoints', points: [[]], times: [0] } }] })],
    ['an unknown preset', JSON.stringify({ ...GOOD, robot: { preset: 'nope' } })],
  ];
  return texts;
}

/** Fragments that are not valid base64url of UTF-8 JSON at all. */
const BAD_FRAGMENTS = [
  ['characters outside base64url', 'scenario=%%%bad'],
  ['padding and +/', 'scenario=ab+/cd=='],
  ['a single character', 'scenario=a'],
  ['bad UTF-8', `scenario=${base64url([0xff, 0xfe, 0x7b, 0x7d])}`],
  ['spaces', 'scenario=abc def'],
];

test('hostile #scenario= links and Open… files show a message, keep the scene and the page running', async () => {
  const r = rng(SEED);
  const browser = await launch({ webgpu: false });
  try {
    const page = await browser.context.newPage();
    const errors = collectErrors(page);
    await page.goto(`${baseUrl}?scenario=planar-transition`);
    await page.evaluate(() => window.playground.ready);
    // The playground runs from the start (the button offers Pause).
    assert.equal(await page.locator('#run').textContent(), 'Pause');
    await frames(page, 3);
    const before = await page.evaluate(() => window.playground.state());
    const messages = [];

    /** Runs `trigger`, then checks the message, the scene and that time goes on. */
    const expectRefused = async (what, trigger) => {
      await page.evaluate(() => { window.playground.app.errorBox.hidden = true; });
      const t0 = (await page.evaluate(() => window.playground.state())).world.t;
      await trigger();
      await page.waitForFunction(() => !window.playground.app.errorBox.hidden, null, { timeout: 15000 }).catch(async () => {
        const status = await page.evaluate(() => window.playground.app.panel.status.textContent);
        assert.fail(`${what}: no message shown within 15 s (status: ${status}; so far: ${messages.length} refused)`);
      });
      const text = await page.evaluate(() => window.playground.app.errorMessage.textContent);
      messages.push(`${what}: ${text.replaceAll('\n', ' / ').slice(0, 160)}`);
      assert.match(text, /unchanged/, `${what}: says the scene is unchanged`);
      assert.ok(text.length < 2000, `${what}: a message a person can read (${text.length} characters)`);
      await frames(page, 4);
      const now = await page.evaluate(() => window.playground.state());
      assert.deepEqual(now.world.obstacles.map((o) => o.id), before.world.obstacles.map((o) => o.id), `${what}: obstacles untouched`);
      assert.equal(now.dof, before.dof, `${what}: the same robot`);
      assert.ok(now.world.t > t0, `${what}: the simulation keeps running`);
      assert.equal(await page.evaluate(() => ({}).polluted), undefined, `${what}: no prototype pollution`);
    };

    for (const [what, fragment] of BAD_FRAGMENTS) {
      await expectRefused(`link, ${what}`, () => page.evaluate((f) => { location.hash = `#${f}`; }, fragment));
    }
    for (const [what, text] of badTexts(r)) {
      await expectRefused(`link, ${what}`, () => page.evaluate((f) => { location.hash = `#${f}`; }, linkOf(text)));
      await expectRefused(`file, ${what}`, () =>
        page.locator('#file').setInputFiles({ name: 'scene.json', mimeType: 'application/json', buffer: Buffer.from(text, 'utf8') }));
    }
    // A link cut short: a valid one truncated.
    const link = encodeShare(GOOD);
    await expectRefused('link, a good one cut short', () => page.evaluate((f) => { location.hash = `#${f}`; }, link.slice(0, link.length - 7)));
    // Too large a file.
    await expectRefused('file, 6 MB', () =>
      page.locator('#file').setInputFiles({ name: 'big.json', mimeType: 'application/json', buffer: Buffer.alloc(6_000_000, 0x20) }));
    // A binary file.
    await expectRefused('file, binary', () =>
      page.locator('#file').setInputFiles({ name: 'image.json', mimeType: 'application/json', buffer: Buffer.from(Array.from({ length: 4096 }, () => r.int(256))) }));

    console.log(`# ${messages.length} hostile links and files, each refused with a message:`);
    for (const m of messages) console.log(`#   ${m}`);

    // A good link still loads afterwards.
    await page.evaluate((f) => { location.hash = `#${f}`; }, encodeShare(GOOD));
    await page.waitForFunction(() => window.playground.state().world.obstacles.some((o) => o.id === 'ball'));
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
  }
});
