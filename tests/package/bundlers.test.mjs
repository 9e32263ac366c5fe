// The npm package in the browser, as a web developer gets it: the packed
// tarball installed into a fresh temporary project, one small app built by
// each bundler (Vite build, webpack 5, esbuild), served by Vite's dev server,
// and loaded by a plain <script type="module"> page (an import map onto the
// package's files, the layout of a static host or a CDN). Every page runs in
// headless Chromium (WebGL2) and must: import `World` and `simulate` from
// `skeleton-avoidance` and run them, draw `<skeleton-playground
// scenario="human-panda">` from `skeleton-avoidance/element`, and do so with
// no failed request and no console error. Each production bundle has a size
// budget (gzipped JS; the wasm separately).
//
// The bundlers are the workspace's pinned devDependencies, driven through
// their JavaScript APIs with the temporary project as their root.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { launch } from '../browser/chromium.mjs';
import { installPackage } from './project.mjs';
import { HTML, app as appSource, checkBudget, checkPage, served } from './pages.mjs';

let project;

before(() => {
  project = installPackage('bundlers');
});

after(() => {
  if (project) fs.rmSync(project, { recursive: true, force: true });
});

/** A folder of the project holding the app and its page. */
function app(name, script) {
  const dir = path.join(project, name);
  fs.mkdirSync(dir, { recursive: true });
  fs.writeFileSync(path.join(dir, 'main.js'), appSource());
  fs.writeFileSync(path.join(dir, 'index.html'), HTML(script));
  return dir;
}

test('Vite build: the production bundle runs the library and draws the element', async () => {
  const { build } = await import('vite');
  const dir = app('vite', '<script type="module" src="./main.js"></script>');
  const dist = path.join(dir, 'dist');
  await build({ root: dir, configFile: false, logLevel: 'warn', build: { outDir: dist, emptyOutDir: true } });
  checkBudget('vite', dist);
  await served(dist, (url) => checkPage(url, 'vite build'));
});

test('Vite dev server: the page runs the library and draws the element', async () => {
  const { createServer } = await import('vite');
  const dir = app('vite-dev', '<script type="module" src="./main.js"></script>');
  const server = await createServer({
    root: dir, configFile: false, logLevel: 'warn', server: { host: '127.0.0.1', port: 0, strictPort: false },
    cacheDir: path.join(dir, '.vite'),
  });
  await server.listen();
  try {
    await checkPage(server.resolvedUrls.local[0], 'vite dev');
  } finally {
    await server.close();
  }
});

test('webpack 5: the production bundle runs the library and draws the element', async () => {
  const { default: webpack } = await import('webpack');
  const dir = app('webpack', '<script src="./main.js"></script>');
  const dist = path.join(dir, 'dist');
  const stats = await new Promise((resolve, reject) => {
    webpack({
      mode: 'production', context: dir, entry: './main.js',
      output: { path: dist, filename: 'main.js', clean: true },
      performance: { hints: false },
    }, (err, s) => (err ? reject(err) : resolve(s)));
  });
  assert.ok(!stats.hasErrors(), stats.toString('errors-only'));
  fs.copyFileSync(path.join(dir, 'index.html'), path.join(dist, 'index.html'));
  checkBudget('webpack', dist);
  await served(dist, (url) => checkPage(url, 'webpack'));
});

test('esbuild: the bundle, with the wasm copied beside it as documented, runs and draws', async () => {
  const esbuild = await import('esbuild');
  const dir = app('esbuild', '<script type="module" src="./main.js"></script>');
  const dist = path.join(dir, 'dist');
  await esbuild.build({
    absWorkingDir: dir, entryPoints: ['main.js'], bundle: true, format: 'esm', minify: true,
    outdir: dist, logLevel: 'warning',
  });
  // esbuild leaves `new URL('skeleton_avoidance_bg.wasm', import.meta.url)` as it is:
  // the wasm goes beside the bundle (docs/js-api.md, "Bundlers").
  fs.copyFileSync(path.join(project, 'node_modules', 'skeleton-avoidance', 'web', 'skeleton_avoidance_bg.wasm'), path.join(dist, 'skeleton_avoidance_bg.wasm'));
  fs.copyFileSync(path.join(dir, 'index.html'), path.join(dist, 'index.html'));
  checkBudget('esbuild', dist);
  await served(dist, (url) => checkPage(url, 'esbuild'));
});

test('a plain <script type="module"> page, no bundler: an import map onto the package files', async () => {
  const map = {
    imports: {
      'skeleton-avoidance': '/node_modules/skeleton-avoidance/index.web.js',
      'skeleton-avoidance/element': '/node_modules/skeleton-avoidance/element/embed.js',
    },
  };
  app('plain', `<script type="importmap">${JSON.stringify(map)}</script>\n<script type="module" src="./main.js"></script>`);
  await served(project, (url) => checkPage(`${url}plain/`, 'plain page'));
});

test('a bundle whose wasm is missing says so: the element shows the message, the import rejects with it', async () => {
  const esbuild = await import('esbuild');
  const dir = path.join(project, 'esbuild-missing');
  fs.mkdirSync(dir, { recursive: true });
  fs.writeFileSync(path.join(dir, 'element.js'), "import 'skeleton-avoidance/element';\n");
  fs.writeFileSync(path.join(dir, 'api.js'), "import { presetNames } from 'skeleton-avoidance';\nwindow.result = presetNames();\n");
  const dist = path.join(dir, 'dist');
  await esbuild.build({ absWorkingDir: dir, entryPoints: ['element.js', 'api.js'], bundle: true, format: 'esm', outdir: dist, logLevel: 'warning' });
  fs.writeFileSync(path.join(dist, 'element.html'), HTML('<script type="module" src="./element.js"></script>'));
  fs.writeFileSync(path.join(dist, 'api.html'), '<!doctype html><title>api</title><link rel="icon" href="data:,"><script type="module" src="./api.js"></script>');
  await served(dist, async (url) => {
    const browser = await launch({ webgpu: false });
    try {
      const page = await browser.context.newPage();
      await page.goto(`${url}element.html`);
      const shown = await page.evaluate(() => document.getElementById('pg').ready.then(() => 'started', () => document.getElementById('pg').shadowRoot.textContent));
      assert.match(shown, /skeleton-avoidance: the WebAssembly module web\/skeleton_avoidance_bg\.wasm could not be loaded/);
      assert.match(shown, /next to the bundle/);
      const api = await browser.context.newPage();
      const failed = api.waitForEvent('pageerror', { timeout: 60_000 });
      await api.goto(`${url}api.html`);
      assert.match((await failed).message, /could not be loaded .*next to the bundle/);
      assert.equal(await api.evaluate(() => window.result), undefined);
    } finally {
      await browser.close();
    }
  });
});
