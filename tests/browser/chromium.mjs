// Launches Debian's Chromium headless through playwright-core, with the flags
// this machine kind needs (see the toolchain notes): network hygiene always,
// plus the four WebGPU flags when WebGPU is wanted.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

/** The repository root, and the git-ignored folder where tests save screenshots. */
export const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
export const artifacts = path.join(repo, 'tests', 'artifacts');

export const CHROMIUM = process.env.CHROMIUM_PATH ?? '/usr/lib/chromium/chromium';

const HYGIENE = [
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync',
  '--no-first-run',
  '--disable-quic',
  '--no-default-browser-check',
  '--disable-domain-reliability',
  '--no-sandbox',
  '--host-resolver-rules=MAP * ~NOTFOUND , EXCLUDE 127.0.0.1',
];

const WEBGPU = [
  '--enable-unsafe-webgpu',
  '--use-vulkan=swiftshader',
  '--use-angle=swiftshader',
  '--enable-features=Vulkan,CDPScreenshotNewSurface,SkipListAccountsWithoutGaiaCookies',
];

/**
 * A fresh persistent context (its own temporary profile, removed by `close`).
 * `webgpu: false` leaves WebGPU off (WebGL2 still works through SwiftShader);
 * `extraArgs` are appended (e.g. `--disable-3d-apis` for a browser without either);
 * `hasTouch` makes a touch screen (for swipes and pinches).
 */
export async function launch({ webgpu = true, extraArgs = [], viewport = { width: 1000, height: 700 }, hasTouch = false } = {}) {
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'skeleton-chromium-'));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: CHROMIUM,
    headless: true,
    args: [...HYGIENE, ...(webgpu ? WEBGPU : []), ...extraArgs],
    viewport,
    deviceScaleFactor: 1,
    hasTouch,
  });
  return {
    context,
    /** The profile folder: the browser's command line names it (scripts/bench-frames.mjs finds its processes so). */
    profile,
    async close() {
      await context.close();
      fs.rmSync(profile, { recursive: true, force: true });
    },
  };
}

/** Collects console errors and uncaught exceptions of `page`. */
export function collectErrors(page) {
  const errors = [];
  page.on('console', (msg) => {
    if (msg.type() === 'error') errors.push(`console: ${msg.text()}`);
  });
  page.on('pageerror', (err) => errors.push(`pageerror: ${err.message}`));
  return errors;
}

/** Resolves after `n` animation frames of `page`. */
export function frames(page, n = 3) {
  return page.evaluate((n) => new Promise((resolve) => {
    const step = (k) => (k === 0 ? resolve() : requestAnimationFrame(() => step(k - 1)));
    step(n);
  }), n);
}
