// The documentation page and the embedding example run on the npm package
// and on nothing else: a folder holding only the packed package (unpacked
// from target/npm/*.tgz, every file of it) and the pages as the site build
// writes them (scripts/site-pages.mjs) — the page and the scripts of its own,
// nothing else from web/. Opened in Chromium, every widget must start and draw
// with no failed request and no console error, and the docs page's Monte
// Carlo study must run its worker from the package. A page that needed a
// module of web/ outside the package would show up as a file of the page's
// own (checked: only docs-study.js is) or 404 here, so the site cannot drift
// from what npm users get.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { packedTarball, unpackPackage, writePages } from '../../scripts/site-pages.mjs';
import { artifacts, launch } from '../browser/chromium.mjs';
import { served } from './pages.mjs';

let root;

before(() => {
  root = fs.mkdtempSync(path.join(os.tmpdir(), 'skeleton-avoidance-pages-'));
  unpackPackage(packedTarball(), root, { all: true });
});

after(() => {
  if (root) fs.rmSync(root, { recursive: true, force: true });
});

/** Opens `page` of the folder; checks every widget starts, runs and draws; returns the tab's problems. */
async function checkWidgets(url, page, label, more = async () => {}) {
  const browser = await launch({ webgpu: false, viewport: { width: 1280, height: 800 } });
  try {
    const tab = await browser.context.newPage();
    const problems = [];
    tab.on('console', (msg) => { if (msg.type() === 'error') problems.push(`console: ${msg.text()}`); });
    tab.on('pageerror', (err) => problems.push(`pageerror: ${err.message}`));
    tab.on('response', (res) => { if (res.status() >= 400) problems.push(`HTTP ${res.status()} ${res.url()}`); });
    tab.on('requestfailed', (req) => problems.push(`failed request ${req.url()}`));
    await tab.goto(`${url}${page}`);
    const count = await tab.evaluate(() => Promise.all([...document.querySelectorAll('skeleton-playground')].map((e) => e.ready)).then((r) => r.length));
    assert.ok(count >= 2, `${label}: ${count} widgets`);
    for (const widget of await tab.locator('skeleton-playground').all()) {
      await widget.scrollIntoViewIfNeeded();
      await tab.waitForFunction((el) => el.playground.snapshot().world.t > 0.1, await widget.elementHandle(), { timeout: 60_000 });
      const triangles = await widget.evaluate((el) => el.playground.viewer.state().triangles);
      assert.ok(triangles > 100, `${label}: a widget drew ${triangles} triangles`);
    }
    await more(tab);
    fs.mkdirSync(artifacts, { recursive: true });
    await tab.screenshot({ path: path.join(artifacts, `package-site-${label}.png`), fullPage: true });
    assert.deepEqual(problems, [], label);
    console.log(`# ${label}: ${count} widgets running on the package alone`);
  } finally {
    await browser.close();
  }
}

test('the docs page and the embedding example run on the package files alone', async () => {
  const own = writePages(root, ['docs.html', 'embed-example.html']);
  // What the pages add to the package: themselves and the docs page's study script.
  assert.deepEqual(own, ['docs-study.js', 'docs.html', 'embed-example.html']);
  for (const file of own) {
    const text = fs.readFileSync(path.join(root, file), 'utf8');
    assert.doesNotMatch(text, /(src="|from '|import\(')\.\/(?!skeleton-avoidance\/|docs-study\.js)/, `${file} refers to a file outside the package`);
  }
  await served(root, async (url) => {
    await checkWidgets(url, 'embed-example.html', 'embed-example');
    await checkWidgets(url, 'docs.html', 'docs', async (tab) => {
      // The Monte Carlo figure: its worker comes from the package's element/.
      await tab.locator('#docs-study-run').click();
      await tab.waitForFunction(() => /\d+ \/ 200 runs|runs in/.test(document.getElementById('docs-study-message').textContent), null, { timeout: 120_000 });
      assert.doesNotMatch(await tab.locator('#docs-study-message').textContent(), /failed/);
    });
  });
});
