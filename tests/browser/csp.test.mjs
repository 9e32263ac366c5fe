// Content-Security-Policy: every page (the playground, the docs page, the
// primitive gallery, the embedding example), served from web/ and from the
// built site in dist/, sets a policy that forbids inline script, and runs
// under it without a single violation (`securitypolicyviolation` events and
// console errors). A control proves the policy is enforced: an inline script
// injected into the page does not run and is reported.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { spawnSync } from 'node:child_process';
import { serve } from '../../scripts/serve.mjs';
import { launch, collectErrors, frames, repo } from './chromium.mjs';

/** Pages and how to know each has started. */
const PAGES = [
  ['index.html?scenario=planar-transition', () => window.playground.ready],
  ['docs.html', () => Promise.all([...document.querySelectorAll('skeleton-playground')].map((e) => e.ready))],
  ['gallery.html?backend=webgl2', () => window.galleryReady],
  ['embed-example.html', () => Promise.all([...document.querySelectorAll('skeleton-playground')].map((e) => e.ready))],
];

/** Records every CSP violation of the page in `window.cspViolations` (before any page script runs). */
function recordViolations() {
  window.cspViolations = [];
  document.addEventListener('securitypolicyviolation', (e) => {
    window.cspViolations.push(`${e.effectiveDirective} blocked ${e.blockedURI || 'inline'} (${e.sourceFile}:${e.lineNumber})`);
  });
}

async function checkSite(root) {
  const site = await serve({ port: 0, root });
  const browser = await launch({ webgpu: false });
  try {
    for (const [page, ready] of PAGES) {
      const tab = await browser.context.newPage();
      const errors = collectErrors(tab);
      await tab.addInitScript(recordViolations);
      await tab.goto(`${site.url}${page}`);
      await tab.evaluate(ready);
      await frames(tab, 5);
      const policy = await tab.evaluate(() => document.querySelector('meta[http-equiv="Content-Security-Policy"]')?.content ?? '');
      const scriptSrc = /script-src ([^;]*)/.exec(policy)?.[1] ?? '';
      assert.match(scriptSrc, /'self'/, `${root}/${page}: script-src 'self' (policy: ${policy})`);
      assert.doesNotMatch(scriptSrc, /'unsafe-inline'|'unsafe-eval'|\*/, `${root}/${page}: no inline script, no eval`);
      assert.deepEqual(await tab.evaluate(() => window.cspViolations), [], `${root}/${page}: no CSP violation`);
      assert.deepEqual(errors, [], `${root}/${page}: no console error`);

      // The control: an injected inline script is refused and reported.
      await tab.evaluate(() => {
        const s = document.createElement('script');
        s.textContent = 'window.inlineRan = true;';
        document.head.append(s);
      });
      await tab.waitForFunction(() => window.cspViolations.length > 0);
      assert.equal(await tab.evaluate(() => window.inlineRan), undefined, `${root}/${page}: inline script blocked`);
      assert.match((await tab.evaluate(() => window.cspViolations))[0], /^script-src/);
      console.log(`# ${root}/${page}: ${policy}`);
      await tab.close();
    }
  } finally {
    await browser.close();
    await new Promise((resolve) => site.server.close(resolve));
  }
}

test('every page served from web/ runs under a CSP that forbids inline script, with no violation', async () => {
  await checkSite('web');
});

test('every page of the built site (dist/) runs under the same CSP, with no violation', async () => {
  const built = spawnSync(process.execPath, [path.join(repo, 'scripts', 'site.mjs'), '--no-wasm'], { cwd: repo, encoding: 'utf8' });
  assert.equal(built.status, 0, built.stderr);
  await checkSite('dist');
});
