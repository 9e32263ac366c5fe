// The plots as a reader uses them (issue 11, "plots worth reading"), in
// headless Chromium with the real mouse, on WebGPU and WebGL2: every line
// named in a legend that wraps, a colour of its own per line, a click on a
// legend key hides and shows its line, a readout under the pointer, the
// influence distance and the speed limits drawn as reference lines, the
// clearance plotted at every sample, time to collision capped and labelled,
// text at 12 px or more with a contrast of 4.5:1 or more.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { serve } from '../../scripts/serve.mjs';
import { COLOURS, TEXT_COLOURS, FONT_PX } from '../../web/plots.js';
import { launch, collectErrors, frames } from './chromium.mjs';
import { decodePng } from './png.mjs';

let server;
let baseUrl;

before(async () => {
  ({ server, url: baseUrl } = await serve({ port: 0 }));
});
after(() => new Promise((resolve) => server.close(resolve)));

/** WCAG relative luminance of `#rrggbb` or `rgb(r, g, b)`. */
function luminance(colour) {
  const hex = colour.match(/^#([0-9a-f]{2})([0-9a-f]{2})([0-9a-f]{2})$/i);
  const rgb = hex ? hex.slice(1).map((x) => parseInt(x, 16)) : colour.match(/\d+(\.\d+)?/g).slice(0, 3).map(Number);
  const [r, g, b] = rgb.map((c) => {
    const s = c / 255;
    return s <= 0.03928 ? s / 12.92 : ((s + 0.055) / 1.055) ** 2.4;
  });
  return 0.2126 * r + 0.7152 * g + 0.0722 * b;
}

function contrast(a, b) {
  const [hi, lo] = [luminance(a), luminance(b)].sort((x, y) => y - x);
  return (hi + 0.05) / (lo + 0.05);
}

test('plot text colours on white and the line colours meet their bounds', () => {
  for (const [name, colour] of Object.entries(TEXT_COLOURS)) {
    assert.ok(contrast(colour, '#ffffff') >= 4.5, `${name} ${colour}: ${contrast(colour, '#ffffff').toFixed(2)}:1`);
  }
  assert.ok(FONT_PX >= 12);
  // Fifteen lines (a dual arm's joints) get fifteen colours.
  assert.equal(new Set(COLOURS.map((c) => c.toLowerCase())).size, COLOURS.length);
  assert.ok(COLOURS.length >= 15);
});

/** Font size and contrast of every text element of the plots, legends, HUD and stats. */
const textStyles = (page) => page.evaluate(() => {
  const root = document.getElementById('playground').shadowRoot;
  const background = (e) => {
    for (let n = e; n; n = n.parentElement ?? n.getRootNode().host) {
      const bg = getComputedStyle(n).backgroundColor;
      if (bg && !/rgba\(.*,\s*0\)$/.test(bg) && bg !== 'transparent') return bg;
    }
    return 'rgb(255, 255, 255)';
  };
  const selectors = ['.legend .key', '.plot-title', '#hud', '#stats'];
  return selectors.flatMap((sel) => [...root.querySelectorAll(sel)].map((e) => ({
    sel, text: e.textContent.slice(0, 20), size: parseFloat(getComputedStyle(e).fontSize), color: getComputedStyle(e).color, background: background(e),
  })));
});

for (const backend of ['webgpu', 'webgl2']) {
  test(`plots: legends, colours, toggles, readout, reference lines, clearance always plotted (${backend})`, async () => {
    const browser = await launch({ webgpu: true, viewport: { width: 1280, height: 800 } });
    try {
      const page = await browser.context.newPage();
      const errors = collectErrors(page);
      await page.goto(`${baseUrl}?scenario=lwr4-elbow&backend=${backend}`);
      await page.evaluate(() => window.playground.ready);
      // Wait for the state (50 plotted samples and 2 s simulated), not for wall time:
      // on a busy machine fewer frames are drawn in a given stretch of time. The
      // clearance line exists only from its first sample on.
      await page.waitForFunction(() => (window.playground.series().clearance.min?.v.length ?? 0) > 50
        && window.playground.state().world.t >= 2, null, { timeout: 120_000 });
      await page.locator('#run').click(); // pause, so that the pixels hold still
      await frames(page, 3);
      const plots = await page.evaluate(() => {
        const app = window.playground.app;
        const root = document.getElementById('playground').shadowRoot;
        return Object.fromEntries(Object.entries(app.plots).map(([key, p]) => [key, {
          series: [...p.series.keys()],
          keys: [...root.querySelectorAll(`#${p.element.id} .legend .key`)].map((k) => ({
            name: k.textContent, swatch: getComputedStyle(k.querySelector('.swatch')).backgroundColor })),
          refs: p.refs.map((r) => ({ v: r.v, label: r.label ?? '' })),
        }]));
      });
      // Every line is named; a 7-joint arm with d ≠ 0 has 14 DH lines.
      for (const [key, p] of Object.entries(plots)) {
        assert.deepEqual(p.keys.map((k) => k.name), p.series, `${key}: a legend key per line`);
        assert.equal(new Set(p.keys.map((k) => k.swatch)).size, p.keys.length, `${key}: a colour per line`);
      }
      assert.equal(plots.dh.series.length, 14, `DH lines: ${plots.dh.series}`);
      assert.equal(plots.qdot.series.length, 7);
      // Reference lines: the influence distance, ± the lowest speed limit.
      assert.ok(plots.clearance.refs.some((r) => r.label === 'influence distance' && r.v > 0));
      const limit = plots.qdot.refs.find((r) => r.label === 'lowest speed limit');
      assert.ok(limit && limit.v > 0 && plots.qdot.refs.some((r) => r.v === -limit.v), JSON.stringify(plots.qdot.refs));
      // The clearance is plotted at every sample, beyond the influence distance too.
      const series = await page.evaluate(() => window.playground.series());
      assert.ok(series.clearance.min.v.length > 50 && series.clearance.min.v.every(Number.isFinite));

      // A click on a legend key hides its line (and the pixels change); a second shows it.
      const canvas = page.locator('#plot-qdot');
      const key = page.locator('#plot-qdot-figure .legend .key').first();
      const before = decodePng(await canvas.screenshot());
      await key.click();
      await frames(page, 2);
      assert.equal(await key.getAttribute('aria-pressed'), 'false');
      assert.equal(await page.evaluate(() => window.playground.app.plots.qdot.series.get('q̇1').hidden), true);
      const hidden = decodePng(await canvas.screenshot());
      assert.ok(differing(before, hidden) > 20, 'hiding q̇1 changes the plot');
      await key.click();
      await frames(page, 2);
      assert.equal(await key.getAttribute('aria-pressed'), 'true');
      // The pointer over the plot draws a readout box (white, with text) by it.
      const box = await canvas.boundingBox();
      await page.mouse.move(box.x + box.width * 0.5, box.y + box.height * 0.5);
      await frames(page, 2);
      const hover = decodePng(await canvas.screenshot());
      console.log(`# pixels changed: hiding q̇1 ${differing(before, hidden)}, the readout ${differing(before, hover)}`);
      assert.ok(differing(before, hover) > 200, 'the readout shows under the pointer');
      await page.mouse.move(box.x + box.width * 0.5, box.y + box.height + 80);
      await frames(page, 2);

      // Text: at least 12 px and 4.5:1 against what it is drawn on.
      const texts = await textStyles(page);
      assert.ok(texts.length >= 25 && ['.legend .key', '.plot-title', '#hud', '#stats'].every((sel) => texts.some((t) => t.sel === sel)), `${texts.length} texts`);
      const worst = texts.reduce((w, t) => (contrast(t.color, t.background) < contrast(w.color, w.background) ? t : w));
      console.log(`# ${texts.length} texts, smallest ${Math.min(...texts.map((t) => t.size))} px, lowest contrast ${contrast(worst.color, worst.background).toFixed(2)}:1 (${worst.sel})`);
      for (const t of texts) {
        assert.ok(t.size >= 12, `${t.sel} "${t.text}": ${t.size} px`);
        assert.ok(contrast(t.color, t.background) >= 4.5, `${t.sel} "${t.text}": ${t.color} on ${t.background}`);
      }
      assert.deepEqual(errors, []);
    } finally {
      await browser.close();
    }
  });
}

test('time to collision is capped at "> 10 s" and says when nothing closes in', async () => {
  const browser = await launch({ webgpu: false });
  try {
    const page = await browser.context.newPage();
    await page.goto(`${baseUrl}?scenario=planar-transition&paused`);
    await page.evaluate(() => window.playground.ready);
    const lines = await page.evaluate(async () => {
      const { hudLines } = await import('./readouts.js');
      const s = { t: 1, minClearance: 0.2, controlPoints: [] };
      return [25168.14, 10.5, 3.14159, Infinity].map((ttc) => hudLines({ ...s, timeToCollision: ttc }, true, 0.35)[2]);
    });
    assert.deepEqual(lines, ['time to collision > 10 s', 'time to collision > 10 s', 'time to collision 3.14 s', 'time to collision —  (nothing closing in)']);
  } finally {
    await browser.close();
  }
});

/** Pixels whose colour differs between two decoded PNGs of the same size. */
function differing(a, b) {
  let n = 0;
  for (let i = 0; i < a.data.length; i += 4) {
    if (Math.abs(a.data[i] - b.data[i]) + Math.abs(a.data[i + 1] - b.data[i + 1]) + Math.abs(a.data[i + 2] - b.data[i + 2]) > 30) n += 1;
  }
  return n;
}

test('a scenario without a controller is shown with the library\'s defaults (influence 0.3 m, perObstacle)', async () => {
  const browser = await launch({ webgpu: false });
  try {
    const page = await browser.context.newPage();
    const errors = collectErrors(page);
    await page.goto(`${baseUrl}?scenario=planar-transition&paused`);
    await page.evaluate(() => window.playground.ready);
    const shown = await page.evaluate(() => {
      const app = window.playground.app;
      const failure = app.loadScenario({
        robot: { preset: 'planar3' }, q0: [0.3, -0.5, 0.4],
        obstacles: [{ id: 'ball', shape: { type: 'sphere', center: [0.5, 0.4, 0], radius: 0.05 } }], dt: 0.001, duration: 5,
      });
      const root = document.getElementById('playground').shadowRoot;
      return {
        failure,
        influence: app.plots.clearance.refs.find((r) => r.label === 'influence distance')?.v,
        selection: root.getElementById('selection').value,
        field: root.getElementById('influence').value,
      };
    });
    assert.deepEqual(shown, { failure: shown.failure, influence: 0.3, selection: 'perObstacle', field: '0.3' });
    assert.ok(!shown.failure, shown.failure);
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
  }
});
