// The Dependability section of the playground's panel: a Monte Carlo study
// of the current scene in a Web Worker (progress bar, Cancel; the scene is
// never touched), its distributions (a histogram of each run's smallest
// clearance, the probabilities with their 95 % intervals), and a risk map: a
// heat map over a horizontal plane at a chosen height of the clearance (or,
// with a library that has `World.riskAt`, the switch probability) of the
// selected obstacle placed at each point, with the arm where it is.
//
// Owns: the section's elements and the running study (`study`: the tests
// read its `report` and `riskValues`). Interface: `sim` (the scene studied),
// `messages` and `selected()` (the selected obstacle's id, or null).
import { clone, errorText, h } from './dom.js';
import { shapeCenter, translateShape } from './shapes.js';

/** Most runs of a study in the page (each run is a full simulation). */
export const MAX_PAGE_RUNS = 1000;
/** Runs per block: the progress bar moves after each. */
const BLOCK = 10;
/** Cells per side of the risk map. */
export const RISK_GRID = 32;
/** The figure placed when no obstacle is selected. */
const PROBE = { type: 'sphere', center: [0, 0, 0], radius: 0.05 };
/** Sensing of a study of a scene sensed exactly (else every run is the same). */
const STUDY_NOISE = { biasBound: 0.01, sigma: 0.003 };

const DECIMAL = /^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d{1,3})?$/;

/** A typed number in [lo, hi] (integer when asked), or throws an Error naming the field. */
function readNumber(input, field, lo, hi, integer = false) {
  const text = input.value.trim();
  if (!DECIMAL.test(text)) throw new Error(`${field}: not a decimal number`);
  const x = Number(text);
  if (integer && !Number.isInteger(x)) throw new Error(`${field}: expected a whole number`);
  if (!(x >= lo && x <= hi)) throw new Error(`${field}: must be in ${lo}..${hi}`);
  return x;
}

/** Millimetres with `digits` decimals (enough to tell a study's values apart: see `digitsFor`). */
const mm = (x, digits = 1) => (x === null || x === undefined ? '—' : `${(x * 1000).toFixed(digits)} mm`);
/** Decimals of millimetres that show a spread of `range` metres (1 to 4). */
const digitsFor = (range) => (range > 0 ? Math.min(4, Math.max(1, Math.ceil(-Math.log10(range * 1000)) + 1)) : 1);
const pct = (x) => `${(x * 100).toFixed(1)} %`;

/**
 * The section: `{ element, context }`; `context` (the host's interface with
 * the section's own state as `study`) is what `refreshDependability` takes.
 */
export function buildDependability(host) {
  const d = {};
  const pg = { sim: host.sim, messages: host.messages, selected: host.selected, study: d };
  const num = (id, value, title) => h('input', { type: 'number', id, value, title });
  d.runs = num('study-runs', '200', `1..${MAX_PAGE_RUNS}`);
  d.duration = num('study-duration', '2', 's per run');
  d.seed = num('study-seed', '1', 'whole number');
  d.runButton = h('button', { type: 'button', id: 'study-run', onclick: () => runStudy(pg) }, 'Run study');
  d.cancelButton = h('button', { type: 'button', id: 'study-cancel', disabled: true, onclick: () => cancelStudy(pg) }, 'Cancel');
  d.progress = h('progress', { id: 'study-progress', max: '1', value: '0', hidden: true });
  d.message = h('div', { class: 'message', id: 'study-message', role: 'status' });
  d.histogram = h('canvas', { id: 'study-histogram', width: 300, height: 130, hidden: true,
    'aria-label': 'histogram of the smallest clearance of each run' });
  d.table = h('table', { class: 'dh', id: 'study-table', hidden: true });
  d.height = h('input', { type: 'range', id: 'risk-height', min: '-1', max: '2', step: '0.01', value: '0',
    oninput: () => { d.heightOut.textContent = `${Number(d.height.value).toFixed(2)} m`; } });
  d.heightOut = h('output', {}, '0.00 m');
  d.riskKind = h('select', { id: 'risk-kind' }, h('option', { value: 'clearance' }, 'clearance'));
  d.riskButton = h('button', { type: 'button', id: 'risk-run', onclick: () => riskMap(pg) }, 'Risk map');
  d.atObstacle = h('button', { type: 'button', id: 'risk-at-obstacle', title: 'the plane through the selected obstacle',
    onclick: () => planeThroughSelected(pg) }, 'through selected');
  d.risk = h('canvas', { id: 'risk-map', width: 300, height: 300, hidden: true,
    'aria-label': 'risk map: the selected obstacle placed at each point of a horizontal plane' });
  d.riskMessage = h('div', { class: 'hint', id: 'risk-message' });
  const field = (label, input) => h('div', { class: 'row' }, h('label', {}, label, input));
  const element = h('section', { id: 'dependability', 'aria-label': 'dependability' },
    h('h3', {}, 'Dependability'),
    h('p', { class: 'hint' }, 'Noisy copies of the scene as it is now, each with its own sensing errors ',
      `(a scene sensed exactly gets bias ≤ ${STUDY_NOISE.biasBound * 1000} mm, σ ${STUDY_NOISE.sigma * 1000} mm).`),
    field('runs', d.runs), field('duration (s)', d.duration), field('seed', d.seed),
    h('div', { class: 'row' }, d.runButton, d.cancelButton, d.progress),
    d.message, d.histogram, d.table,
    h('div', { class: 'row' }, h('label', {}, 'plane height', d.height, d.heightOut), d.atObstacle),
    h('div', { class: 'row' }, d.riskKind, d.riskButton),
    d.risk, d.riskMessage);
  return { element, context: pg };
}

/** Called when the scene changes: offers the switch probability when the library has it, sets the plane height. */
export function refreshDependability(pg) {
  const d = pg.study;
  if (!d || !pg.sim.world) return;
  if (typeof pg.sim.world.riskAt === 'function' && d.riskKind.options.length === 1) {
    d.riskKind.append(h('option', { value: 'switchProbability' }, 'switch probability'));
  }
  // The plane spans the arm's heights; it starts at their middle.
  const zs = pg.sim.world.state(pg.sim.world.eventCount).skeleton.nodes.map((n) => n[2]);
  const [lo, hi] = [Math.min(...zs), Math.max(...zs)];
  d.height.min = String((lo - 0.3).toFixed(2));
  d.height.max = String((hi + 0.3).toFixed(2));
  d.height.value = String(((lo + hi) / 2).toFixed(2));
  d.heightOut.textContent = `${Number(d.height.value).toFixed(2)} m`;
}

/** Puts the plane through the selected obstacle's centre (a message when none is selected). */
function planeThroughSelected(pg) {
  const d = pg.study;
  const shape = pg.selected() && pg.sim.shapeOf(pg.selected());
  if (!shape) {
    d.riskMessage.textContent = 'Select an obstacle first (click it in the view or in the list).';
    return;
  }
  const z = shapeCenter(shape)[2];
  d.height.min = String(Math.min(Number(d.height.min), z));
  d.height.max = String(Math.max(Number(d.height.max), z));
  d.height.value = String(z);
  d.heightOut.textContent = `${z.toFixed(2)} m`;
}

// ---- the study ----

function studyScenario(pg, duration) {
  const s = clone(pg.sim.currentScenario());
  s.duration = duration;
  const sensing = s.sensing ?? {};
  const noisy = Object.values(sensing).some((v) => v && Object.entries(v).some(([k, x]) => k !== 'seed' && x > 0));
  if (!noisy) s.sensing = { default: { ...STUDY_NOISE } };
  return s;
}

/**
 * Runs a study of `scenario` in a module worker (`study-worker.js`), in blocks
 * of 10 runs: `onProgress(done, runs)` after each, then `onDone(report)` (rows
 * kept) or `onError(message)`. Returns `{ cancel() }`, which ends the worker
 * at once (no callback follows).
 */
export function startStudy({ scenario, runs, seed, onProgress, onDone, onError }) {
  const worker = new Worker(new URL('./study-worker.js', import.meta.url), { type: 'module' });
  let live = true;
  const end = () => {
    live = false;
    worker.terminate();
  };
  worker.onmessage = ({ data }) => {
    if (!live) return;
    if (data.type === 'progress') return onProgress?.(data.done, data.runs);
    end();
    if (data.type === 'done') onDone(data.report);
    else onError(data.message);
  };
  worker.onerror = (e) => {
    if (!live) return;
    end();
    onError(e.message || 'the worker could not start');
  };
  worker.postMessage({ scenario, runs, seed, block: BLOCK });
  return { cancel: end };
}

function runStudy(pg) {
  const d = pg.study;
  let runs;
  let duration;
  let seed;
  try {
    runs = readNumber(d.runs, 'runs', 1, MAX_PAGE_RUNS, true);
    duration = readNumber(d.duration, 'duration', 0.001, 30);
    seed = readNumber(d.seed, 'seed', 0, Number.MAX_SAFE_INTEGER, true);
  } catch (err) {
    d.message.textContent = errorText(err);
    return;
  }
  cancelStudy(pg, false);
  d.runButton.disabled = true;
  d.cancelButton.disabled = false;
  d.progress.hidden = false;
  d.progress.value = 0;
  d.message.textContent = `running ${runs} runs of ${duration} s…`;
  const started = performance.now();
  d.worker = startStudy({
    scenario: studyScenario(pg, duration),
    runs,
    seed,
    onProgress: (done) => {
      d.progress.value = done / runs;
      d.message.textContent = `${done} / ${runs} runs`;
    },
    onDone: (report) => {
      finish(pg);
      d.report = report;
      d.message.textContent = `${runs} runs in ${((performance.now() - started) / 1000).toFixed(1)} s (seed ${seed})`;
      showReport(d, report);
    },
    onError: (message) => {
      finish(pg);
      d.message.textContent = `The study failed: ${message}`;
    },
  });
}

function finish(pg) {
  const d = pg.study;
  d.worker?.cancel();
  d.worker = null;
  d.runButton.disabled = false;
  d.cancelButton.disabled = true;
  d.progress.hidden = true;
}

function cancelStudy(pg, say = true) {
  const d = pg.study;
  if (!d.worker) return;
  finish(pg);
  if (say) d.message.textContent = 'Study cancelled; the scene is unchanged.';
}

/** Fills `d.table` (probabilities, clearance, switches) and `d.histogram` from report `r`. */
export function showReport(d, r) {
  const q = r.minClearance;
  const digits = digitsFor((q.max ?? 0) - (q.min ?? 0));
  const row = (name, p) => h('tr', {}, h('td', {}, name), h('td', {}, pct(p.p)), h('td', {}, `${pct(p.low)} – ${pct(p.high)}`));
  d.table.replaceChildren(
    h('caption', {}, 'per run (95 % Wilson intervals)'),
    h('tr', {}, h('th', {}, ''), h('th', {}, 'p'), h('th', {}, '95 %')),
    row('contact while moving', r.contactWhileMoving), row('stop', r.stop), row('chattering', r.chattering),
    row('transition too slow', r.transitionTooSlow),
    h('tr', {}, h('td', {}, 'clearance min / 5 % / 50 % / max'),
      h('td', { colspan: '2' }, [q.min, q.p05, q.p50, q.max].map((x) => mm(x, digits)).join(' / '))),
    h('tr', {}, h('td', {}, 'switches per second'), h('td', { colspan: '2' }, `mean ${r.switchesPerSecond.mean.toFixed(1)}, max ${r.switchesPerSecond.max.toFixed(1)}`)));
  d.table.hidden = false;
  drawHistogram(d.histogram, (r.rows ?? []).map((x) => x.minClearance).filter((x) => x !== null), q.outOfReach);
}

/** Bars of the smallest clearance per run (mm), 20 bins between the smallest and the largest. */
export function drawHistogram(canvas, values, outOfReach) {
  canvas.hidden = false;
  const ctx = canvas.getContext('2d');
  const { width: w, height: hgt } = canvas;
  ctx.clearRect(0, 0, w, hgt);
  ctx.fillStyle = '#fff';
  ctx.fillRect(0, 0, w, hgt);
  ctx.font = '11px system-ui, sans-serif';
  ctx.fillStyle = '#333';
  if (!values.length) {
    ctx.fillText(`no run came within reach (${outOfReach})`, 8, hgt / 2);
    return [];
  }
  const lo = Math.min(...values);
  const hi = Math.max(...values);
  const bins = 20;
  const counts = new Array(bins).fill(0);
  for (const v of values) counts[hi > lo ? Math.min(bins - 1, Math.floor(((v - lo) / (hi - lo)) * bins)) : 0] += 1;
  const top = Math.max(...counts);
  const [x0, y0, pw, ph] = [8, 14, w - 16, hgt - 34];
  ctx.fillText(`runs per bin (largest ${top}); ${values.length} runs`, x0, 10);
  for (let k = 0; k < bins; k++) {
    const bh = (counts[k] / top) * ph;
    ctx.fillStyle = lo + ((hi - lo) * (k + 0.5)) / bins <= 0 ? '#c0392b' : '#2e86c1';
    ctx.fillRect(x0 + (k * pw) / bins + 1, y0 + ph - bh, pw / bins - 2, bh);
  }
  ctx.fillStyle = '#333';
  const digits = digitsFor(hi - lo);
  ctx.fillText(mm(lo, digits), x0, hgt - 6);
  const right = mm(hi, digits);
  ctx.fillText(right, w - 8 - ctx.measureText(right).width, hgt - 6);
  ctx.fillText('smallest clearance', w / 2 - 45, hgt - 6);
  return counts;
}

// ---- the risk map ----

/** Extent of the map: a square around the base holding the arm's reach. */
function mapExtent(state) {
  const nodes = state.skeleton.nodes;
  const [bx, by] = nodes[0];
  const reach = Math.max(0.2, ...nodes.map(([x, y]) => Math.hypot(x - bx, y - by)));
  return { cx: bx, cy: by, half: reach + 0.15 };
}

function riskMap(pg) {
  const d = pg.study;
  pg.messages.guard(() => {
    const state = pg.sim.world.state(pg.sim.world.eventCount);
    const z = Number(d.height.value);
    const selected = pg.selected() && state.obstacles.find((o) => o.id === pg.selected());
    const shape = selected ? selected.shape : PROBE;
    const c0 = shapeCenter(shape);
    const { cx, cy, half } = mapExtent(state);
    const kind = d.riskKind.value;
    const sensing = riskSensing(pg, selected?.id);
    const values = [];
    for (let j = 0; j < RISK_GRID; j++) {
      for (let i = 0; i < RISK_GRID; i++) {
        const p = [cx - half + ((i + 0.5) * 2 * half) / RISK_GRID, cy + half - ((j + 0.5) * 2 * half) / RISK_GRID, z];
        const placed = translateShape(shape, [p[0] - c0[0], p[1] - c0[1], p[2] - c0[2]]);
        values.push(kind === 'clearance' ? pg.sim.world.clearanceTo(placed) : pg.sim.world.riskAt(placed, sensing).switchProbability);
      }
    }
    const influence = pg.sim.influence();
    d.riskValues = { kind, values, extent: { cx, cy, half }, z };
    drawRisk(d.risk, d.riskValues, influence, state);
    d.riskMessage.textContent = `${selected ? `“${selected.id}”` : 'a 5 cm sphere'} placed at ${RISK_GRID}×${RISK_GRID} points at z = ${z.toFixed(2)} m; ` +
      (kind === 'clearance' ? `red: contact, green: beyond the influence distance (${influence} m)`
        : `probability that the sensed closest segment is not the true one (sensing ${JSON.stringify(sensing)}): green 0, yellow ½, red 1`);
  });
}

/** The sensing of obstacle `id` in the scene (its own, else the default), or the study's noise when it is exact. */
function riskSensing(pg, id) {
  const sensing = pg.sim.scenario.sensing ?? {};
  const spec = (id && sensing[id]) || sensing.default || {};
  const noisy = Object.entries(spec).some(([k, x]) => k !== 'seed' && k !== 'latency' && x > 0);
  return noisy ? spec : { ...STUDY_NOISE };
}

/** Colour of a value in [0, 1] (0 red, ½ yellow, 1 green). */
function ramp(t) {
  const u = Math.max(0, Math.min(1, t));
  const r = u < 0.5 ? 220 : Math.round(220 * (1 - u) * 2);
  const g = u < 0.5 ? Math.round(60 + 340 * u) : 200;
  return `rgb(${r},${g},70)`;
}

function drawRisk(canvas, map, influence, state) {
  canvas.hidden = false;
  const ctx = canvas.getContext('2d');
  const { width: w, height: hgt } = canvas;
  const cell = w / RISK_GRID;
  map.values.forEach((v, k) => {
    const [i, j] = [k % RISK_GRID, Math.floor(k / RISK_GRID)];
    ctx.fillStyle = map.kind === 'clearance' ? (v <= 0 ? '#7b1010' : ramp(v / influence)) : ramp(1 - v);
    ctx.fillRect(i * cell, j * cell, Math.ceil(cell), Math.ceil(cell));
  });
  // The arm seen from above.
  const { cx, cy, half } = map.extent;
  const px = ([x, y]) => [((x - cx + half) / (2 * half)) * w, ((cy + half - y) / (2 * half)) * hgt];
  ctx.strokeStyle = '#111';
  ctx.lineWidth = 3;
  for (const s of state.skeleton.segments) {
    const [a, b] = [px(state.skeleton.nodes[s.from]), px(state.skeleton.nodes[s.to])];
    ctx.beginPath();
    ctx.moveTo(a[0], a[1]);
    ctx.lineTo(b[0], b[1]);
    ctx.stroke();
  }
  ctx.fillStyle = '#111';
  ctx.font = '11px system-ui, sans-serif';
  ctx.fillText(`x →  ${(2 * half).toFixed(2)} m across, top view`, 6, hgt - 6);
}
