// `skeleton-avoidance/compat` and `skeleton-avoidance/compat/element`: the
// entries with the WebAssembly inlined (base64), for bundlers and hosts that
// cannot serve or locate a separate .wasm file. The packed tarball is
// installed into a fresh project and bundled by esbuild (and by Vite, which
// must not emit the wasm as an asset), and the bundle is served WITHOUT any
// .wasm file: the page must import `World` and `simulate`
// and run them, draw `<skeleton-playground scenario="human-panda">`, request
// no .wasm, and show no failed request and no console error. A page whose
// Content-Security-Policy forbids compiling WebAssembly gets one Error that
// names the entry and the cause, in the import and inside the element.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { launch } from '../browser/chromium.mjs';
import { installPackage } from './project.mjs';
import { HTML, app, checkBudget, checkPage, served } from './pages.mjs';

let project;

before(() => {
  project = installPackage('compat');
});

after(() => {
  if (project) fs.rmSync(project, { recursive: true, force: true });
});

/** Bundles `entries` (name → source) of a project folder with esbuild into its dist/. */
async function bundle(name, entries) {
  const esbuild = await import('esbuild');
  const dir = path.join(project, name);
  fs.mkdirSync(dir, { recursive: true });
  for (const [file, source] of Object.entries(entries)) fs.writeFileSync(path.join(dir, file), source);
  const dist = path.join(dir, 'dist');
  await esbuild.build({
    absWorkingDir: dir, entryPoints: Object.keys(entries), bundle: true, format: 'esm', minify: true,
    outdir: dist, logLevel: 'warning',
  });
  return dist;
}

test('esbuild, compat: the bundle runs and draws with no .wasm file anywhere', async () => {
  const dist = await bundle('esbuild-compat', { 'main.js': app('skeleton-avoidance/compat') });
  fs.writeFileSync(path.join(dist, 'index.html'), HTML('<script type="module" src="./main.js"></script>'));
  // Nothing else is copied: the bundle is the page's only script and holds the module.
  checkBudget('esbuild compat', dist, { inlined: true });
  const bundled = fs.readFileSync(path.join(dist, 'main.js'), 'utf8');
  assert.doesNotMatch(bundled, /skeleton_avoidance_bg\.wasm/, 'the compat bundle still names the .wasm file');
  await served(dist, (url) => checkPage(url, 'esbuild compat'));
});

test('Vite build, compat: the production bundle emits no .wasm and runs and draws', async () => {
  const { build } = await import('vite');
  const dir = path.join(project, 'vite-compat');
  fs.mkdirSync(dir, { recursive: true });
  fs.writeFileSync(path.join(dir, 'main.js'), app('skeleton-avoidance/compat'));
  fs.writeFileSync(path.join(dir, 'index.html'), HTML('<script type="module" src="./main.js"></script>'));
  const dist = path.join(dir, 'dist');
  await build({ root: dir, configFile: false, logLevel: 'warn', build: { outDir: dist, emptyOutDir: true, chunkSizeWarningLimit: 8000 } });
  checkBudget('vite compat', dist, { inlined: true });
  await served(dist, (url) => checkPage(url, 'vite compat'));
});

test('compat on a page whose Content-Security-Policy forbids WebAssembly: one Error naming the entry and the cause', async () => {
  const dist = await bundle('esbuild-compat-csp', {
    'element.js': "import 'skeleton-avoidance/compat/element';\n",
    'api.js': "import { presetNames } from 'skeleton-avoidance/compat';\nwindow.result = presetNames();\n",
  });
  const csp = `<meta http-equiv="Content-Security-Policy" content="script-src 'self'">`;
  fs.writeFileSync(path.join(dist, 'element.html'), HTML('<script type="module" src="./element.js"></script>').replace('<head>', `<head>${csp}`));
  fs.writeFileSync(path.join(dist, 'api.html'), `<!doctype html><head>${csp}<title>api</title><link rel="icon" href="data:,"></head><script type="module" src="./api.js"></script>`);
  await served(dist, async (url) => {
    const browser = await launch({ webgpu: false });
    try {
      const page = await browser.context.newPage();
      await page.goto(`${url}element.html`);
      const shown = await page.evaluate(() => document.getElementById('pg').ready.then(() => 'started', () => document.getElementById('pg').shadowRoot.textContent));
      assert.match(shown, /skeleton-avoidance\/compat: the inlined WebAssembly module could not be compiled or instantiated \(.+\)/);
      assert.match(shown, /must allow 'wasm-unsafe-eval'/);
      const api = await browser.context.newPage();
      const failed = api.waitForEvent('pageerror', { timeout: 60_000 });
      await api.goto(`${url}api.html`);
      assert.match((await failed).message, /skeleton-avoidance\/compat: the inlined WebAssembly module could not be compiled .*'wasm-unsafe-eval'/);
      assert.equal(await api.evaluate(() => window.result), undefined);
    } finally {
      await browser.close();
    }
  });
});
