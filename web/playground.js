// The playground widget: a simulated world (the library's `World`) drawn by
// the wgpu `Viewer`, with the panel, plots, picking and dragging, scenarios
// and the stats overlay. `web/embed.js` wraps it as <skeleton-playground>;
// the full page is one such element filling the window.
//
// Everything the person types or loads is shown with textContent, never as
// HTML. Every failure is shown in the widget and leaves the scene as it was.
import { TimePlot } from './plots.js';
import { decodeShare, downloadScenario, encodeShare, readScenarioFile } from './scenario-io.js';
import { STYLE } from './style.js';

let wasmModule = null;

/** Loads and initialises the wasm package once per page (it sits in ./pkg/ beside this file). */
export function loadWasm() {
  wasmModule ??= import(new URL('./pkg/skeleton_avoidance.js', import.meta.url).href).then(async (m) => {
    await m.default();
    return m;
  });
  return wasmModule;
}

/**
 * Whether the browser's WebGPU adapter is a software rasteriser (SwiftShader):
 * the renderer then draws without multisampling, which halves its cost there.
 * (Under WebGL2 the renderer reads the adapter name itself.)
 */
async function softwareWebGpu() {
  try {
    const info = (await navigator.gpu?.requestAdapter())?.info;
    return Boolean(info && (info.isFallbackAdapter || /swiftshader|llvmpipe|lavapipe/i.test(`${info.architecture} ${info.description}`)));
  } catch {
    return false;
  }
}

export const PRESETS = ['planar3', 'lwr4', 'panda', 'ur5', 'dual-arm'];
export const PALETTE = ['point', 'segment', 'sphere', 'capsule', 'plane', 'rectangle', 'disk', 'polygon', 'box', 'human'];

const errorText = (err) => (err instanceof Error ? err.message : String(err));
const clone = (x) => (x === undefined ? undefined : JSON.parse(JSON.stringify(x)));

/** `h('div', { class: 'x', onclick }, child, 'text')`: text children become text nodes. */
function h(tag, attrs = {}, ...children) {
  const el = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v === undefined || v === null || v === false) continue;
    if (k.startsWith('on')) el.addEventListener(k.slice(2), v);
    else if (k === 'class') el.className = v;
    else if (k in el && typeof v !== 'string') el[k] = v;
    else el.setAttribute(k, v === true ? '' : v);
  }
  for (const c of children.flat()) {
    if (c === null || c === undefined || c === false) continue;
    el.append(typeof c === 'string' || typeof c === 'number' ? document.createTextNode(String(c)) : c);
  }
  return el;
}

// ---- shapes: translate, scale, rotate (plain objects of the JS contract) ----

const add = (a, b) => a.map((x, k) => x + b[k]);
const sub = (a, b) => a.map((x, k) => x - b[k]);
const mul = (a, s) => a.map((x) => x * s);
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const len = (a) => Math.hypot(...a);
const isPoint = (p) => Array.isArray(p) && p.length === 3 && p.every((x) => typeof x === 'number');

/** Applies `f` to every point of a shape (recursing into composite parts). */
function mapPoints(shape, f) {
  const out = { ...shape };
  for (const key of ['p', 'a', 'b', 'center', 'position']) if (isPoint(out[key])) out[key] = f(out[key]);
  for (const key of ['vertices', 'points']) if (Array.isArray(out[key])) out[key] = out[key].map((p) => (isPoint(p) ? f(p) : p));
  if (Array.isArray(out.parts)) out.parts = out.parts.map((part) => mapPoints(part, f));
  return out;
}

/** The shape moved by `delta` (m). */
export function translateShape(shape, delta) {
  const out = mapPoints(shape, (p) => add(p, delta));
  if (shape.type === 'plane') out.offset = shape.offset - dot(shape.normal, delta);
  return out;
}

/** A representative point: the centre. */
export function shapeCenter(shape) {
  switch (shape.type) {
    case 'point': return shape.p;
    case 'segment': case 'capsule': case 'taperedCapsule': return mul(add(shape.a, shape.b), 0.5);
    case 'plane': { const n = shape.normal; return mul(n, -shape.offset / dot(n, n)); }
    case 'polygon': return mul(shape.vertices.reduce(add, [0, 0, 0]), 1 / shape.vertices.length);
    default: {
      if (isPoint(shape.center)) return shape.center;
      if (isPoint(shape.position)) return shape.position;
      const pts = [];
      mapPoints(shape, (p) => { pts.push(p); return p; });
      return pts.length ? mul(pts.reduce(add, [0, 0, 0]), 1 / pts.length) : [0, 0, 0];
    }
  }
}

/** The shape scaled by `s` about its centre. */
export function scaleShape(shape, s) {
  const c = shapeCenter(shape);
  const out = mapPoints(shape, (p) => add(c, mul(sub(p, c), s)));
  for (const key of ['radius', 'height', 'scale']) {
    if (typeof out[key] === 'number') out[key] *= s;
    else if (Array.isArray(out[key])) out[key] = out[key].map((r) => r * s);
  }
  if (Array.isArray(out.halfExtents)) out.halfExtents = out.halfExtents.map((r) => r * s);
  if (Array.isArray(out.parts)) out.parts = out.parts.map((p) => ({ ...p, ...(typeof p.radius === 'number' ? { radius: p.radius * s } : {}) }));
  return out;
}

function rotate(v, axis, angle) {
  const [x, y, z] = axis;
  const c = Math.cos(angle);
  const s = Math.sin(angle);
  const d = dot(axis, v);
  return [
    v[0] * c + (y * v[2] - z * v[1]) * s + x * d * (1 - c),
    v[1] * c + (z * v[0] - x * v[2]) * s + y * d * (1 - c),
    v[2] * c + (x * v[1] - y * v[0]) * s + z * d * (1 - c),
  ];
}

function quatMul(a, b) {
  const [ax, ay, az, aw] = a;
  const [bx, by, bz, bw] = b;
  return [aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz];
}

/** The shape rotated by `angle` (rad) about the world `axis` through its centre. */
export function rotateShape(shape, axis, angle) {
  const c = shapeCenter(shape);
  const out = mapPoints(shape, (p) => add(c, rotate(sub(p, c), axis, angle)));
  if (isPoint(shape.normal)) out.normal = rotate(shape.normal, axis, angle);
  if (shape.type === 'plane') out.offset = -dot(out.normal, c);
  if (Array.isArray(shape.axes)) out.axes = shape.axes.map((a) => rotate(a, axis, angle));
  if (shape.type === 'human' && Math.abs(axis[2]) > 0.99) out.heading = (shape.heading ?? 0) + Math.sign(axis[2]) * angle;
  if (shape.type === 'box') {
    const q = [...mul(axis, Math.sin(angle / 2)), Math.cos(angle / 2)];
    out.rotation = quatMul(q, shape.rotation ?? [0, 0, 0, 1]);
  }
  return out;
}

/** A new shape of `type` around `c` (m), sized for an arm of reach `r` (m). */
export function defaultShape(type, c, r) {
  const s = Math.max(0.04, 0.12 * r);
  switch (type) {
    case 'point': return { type, p: c };
    case 'segment': return { type, a: add(c, [0, -s, 0]), b: add(c, [0, s, 0]) };
    case 'sphere': return { type, center: c, radius: 0.6 * s };
    case 'capsule': return { type, a: add(c, [0, -s, 0]), b: add(c, [0, s, 0]), radius: 0.4 * s };
    case 'plane': { const n = [-1, 0, 0]; return { type, normal: n, offset: -dot(n, c) }; }
    case 'rectangle': return { type, center: c, axes: [[1, 0, 0], [0, 1, 0]], halfExtents: [s, 0.6 * s] };
    case 'disk': return { type, center: c, normal: [0, 0, 1], radius: 0.8 * s };
    case 'polygon': return { type, vertices: [0, 1, 2, 3, 4].map((k) => add(c, [s * Math.cos(k * 1.2566), s * Math.sin(k * 1.2566), 0])) };
    case 'box': return { type, center: c, halfExtents: [0.6 * s, 0.8 * s, 0.5 * s], rotation: [0, 0, 0, 1] };
    case 'human': return { type, position: [c[0], c[1], 0], heading: Math.atan2(-c[1], -c[0]), height: 1.75 };
    default: throw new Error(`unknown obstacle type ${type}`);
  }
}

// ---- the widget ----

const HELP = [
  ['Space', 'pause / run'],
  ['S or .', 'single control step (while paused)'],
  ['R', 'reset the simulation'],
  ['1 … 0', 'add point, segment, sphere, capsule, plane, rectangle, disk, polygon, box, human'],
  ['Click', 'select an obstacle (drag it on the plane facing you)'],
  ['Alt + drag', 'move the obstacle along the view direction'],
  ['Delete', 'delete the selected obstacle'],
  ['[ / ]', 'shrink / grow the selected obstacle'],
  ['Q / E', 'rotate the selected obstacle about z'],
  ['Escape', 'deselect, close this help'],
  ['V', 'next camera view'],
  ['Drag empty space', 'orbit (3D) or pan (2D); right or Shift + drag pans; wheel zooms'],
  ['?', 'this help'],
];

/** Frames between refreshes of the plots and the text over the view. */
const REFRESH_EVERY = 10;

const EVENT_TEXT = {
  segmentSwitch: 'control point switches segment',
  transitionTooSlow: 'transition slower than the time to collision',
  transitionStart: 'transition starts',
  transitionEnd: 'transition ends',
  chattering: 'chattering detected',
  stop: 'robot stopped',
  lock: 'control point locked',
};

export class Playground {
  /**
   * @param {ShadowRoot|HTMLElement} root where the widget builds its DOM
   * @param {{ controls?: 'full'|'minimal'|'none', backend?: string, view?: string,
   *           speed?: number, plot?: string, keyboardTarget?: EventTarget }} options
   */
  constructor(root, options = {}) {
    this.root = root;
    this.options = options;
    this.controls = options.controls ?? 'full';
    this.speed = options.speed ?? 1;
    this.running = true;
    this.world = null;
    this.viewer = null;
    this.wasm = null;
    this.scenario = null;
    this.state = null;
    this.selected = null;
    this.frames = 0;
    this.acc = 0;
    this.pendingSteps = 0;
    this.seenEvents = 0;
    this.stats = { fps: 0, frameMs: 0, stepsPerFrame: 0, stepMs: 0, drawMs: 0 };
    this.frameTimes = [];
    this.robotSpec = null;
    this.build();
  }

  // ---- DOM ----

  build() {
    const style = h('style', {}, STYLE);
    this.canvas = h('canvas', { class: 'view', id: 'view', tabindex: '0', 'aria-label': 'Robot and obstacles' });
    this.statsBox = h('div', { class: 'stats', id: 'stats', 'aria-hidden': 'true' });
    this.hud = h('div', { class: 'hud', id: 'hud' });
    this.notices = h('div', { class: 'notices', id: 'notices', 'aria-live': 'polite' });
    this.errorMessage = h('span');
    this.errorBox = h('div', { class: 'error', id: 'error', role: 'alert', hidden: true },
      h('button', { type: 'button', onclick: () => { this.errorBox.hidden = true; } }, 'dismiss'), this.errorMessage);
    this.helpBox = h('div', { class: 'help', id: 'help', hidden: true },
      h('strong', {}, 'Keyboard and mouse'),
      h('table', {}, HELP.map(([k, what]) => h('tr', {}, h('td', {}, h('kbd', {}, k)), h('td', {}, what)))),
      h('p', { class: 'hint' }, 'Press ? or Escape to close.'));
    const stage = h('div', { class: 'stage' }, this.canvas, this.statsBox, this.hud, this.notices, this.errorBox, this.helpBox);

    this.plots = {
      clearance: new TimePlot(h('canvas', { id: 'plot-clearance' }), { title: 'clearance', unit: 'm', min: 0 }),
      dh: new TimePlot(h('canvas', { id: 'plot-dh' }), { title: 'control point DH values', unit: 'm' }),
      qdot: new TimePlot(h('canvas', { id: 'plot-qdot' }), { title: 'joint velocities', unit: 'rad/s' }),
    };
    const wanted = this.controls === 'full' ? Object.keys(this.plots) : (this.options.plot ? [this.options.plot] : []);
    const plots = h('div', { class: 'plots' }, wanted.filter((k) => this.plots[k]).map((k) => this.plots[k].canvas));
    this.shownPlots = wanted.filter((k) => this.plots[k]);

    const cls = `sp ${this.controls}${this.options.plot ? ' with-plot' : ''}${this.options.stats ? ' with-stats' : ''}`;
    this.container = h('div', { class: cls }, stage, plots);
    if (this.controls === 'full') this.container.append(this.buildPanel());
    else if (this.controls === 'minimal') this.container.append(this.buildBar());
    this.root.append(style, this.container);
  }

  buildBar() {
    this.title = h('span', { class: 'title' });
    this.playButton = h('button', { type: 'button', onclick: () => this.toggleRun() }, 'Pause');
    return h('div', { class: 'bar' },
      this.playButton,
      h('button', { type: 'button', onclick: () => this.reset() }, 'Reset'),
      this.title);
  }

  field(label, input) {
    return h('div', { class: 'row' }, h('label', {}, label, input));
  }

  buildPanel() {
    const p = {};
    this.panel = p;
    p.example = h('select', { id: 'example', 'aria-label': 'example scenario' });
    p.file = h('input', { type: 'file', accept: '.json,application/json', hidden: true, id: 'file',
      onchange: () => this.loadFile(p.file.files[0]) });
    p.status = h('div', { class: 'hint', id: 'status', 'aria-live': 'polite' });
    p.playButton = h('button', { type: 'button', id: 'run', onclick: () => this.toggleRun() }, 'Pause');
    this.playButton = p.playButton;
    p.speed = h('input', { type: 'range', id: 'speed', min: '-3', max: '1', step: '0.01', value: String(Math.log2(this.speed) / 2),
      oninput: () => { this.speed = 4 ** Number(p.speed.value); p.speedOut.textContent = `${this.speed.toFixed(2)}×`; } });
    p.speedOut = h('output', {}, `${this.speed.toFixed(2)}×`);

    p.preset = h('select', { id: 'preset', onchange: () => this.setPreset(p.preset.value) },
      PRESETS.map((n) => h('option', { value: n }, n)), h('option', { value: 'custom' }, 'custom (DH table)'));
    p.convention = h('select', { id: 'convention' }, h('option', { value: 'standard' }, 'standard DH'), h('option', { value: 'modified' }, 'modified DH'));
    p.dh = h('tbody');
    p.dhMessage = h('div', { class: 'message', id: 'dh-message', role: 'status' });
    p.joints = h('div', { id: 'joints' });

    const num = (id, step, title) => h('input', { type: 'number', id, step, placeholder: 'default', title });
    p.mode = h('select', { id: 'mode' }, ['velocity', 'torque', 'clik2'].map((m) => h('option', { value: m }, m)));
    p.selection = h('select', { id: 'selection' }, ['pairs', 'perObstacle', 'pinned'].map((m) => h('option', { value: m }, m)));
    p.influenceDistance = num('influence', '0.01', 'm');
    p.repulsionGain = num('gain', '0.1', '');
    p.maxRepulsionSpeed = num('max-speed', '0.05', 'm/s');
    p.transitionTime = num('transition-time', '0.01', 's per DH value');
    p.controllerMessage = h('div', { class: 'message', id: 'controller-message' });
    for (const key of ['mode', 'selection']) p[key].addEventListener('change', () => this.setController({ [key]: p[key].value }));
    for (const key of ['influenceDistance', 'repulsionGain', 'maxRepulsionSpeed', 'transitionTime']) {
      p[key].addEventListener('change', () => {
        if (p[key].value === '') return;
        this.setController({ [key]: Number(p[key].value) });
      });
    }
    p.bound = num('noise-bound', '0.005', 'm');
    p.sigma = num('noise-sigma', '0.005', 'm');
    p.switchWindow = num('switch-window', '0.1', 's');
    p.maxSwitches = num('max-switches', '1', '');
    p.onChattering = h('select', { id: 'on-chattering' }, ['stop', 'lock'].map((m) => h('option', { value: m }, m)));
    p.lockTime = num('lock-time', '0.1', 's');
    p.worldMessage = h('div', { class: 'message', id: 'world-message' });

    p.obstacles = h('ul', { class: 'obstacles', id: 'obstacle-list' });
    p.selectedBox = h('div', { id: 'selected' });

    p.viewSelect = h('select', { id: 'view-select', onchange: () => this.guard(() => this.viewer.setView(p.viewSelect.value)) },
      [['auto', 'auto'], ['3d', '3D'], ['top', 'top'], ['front', 'front'], ['side', 'side']].map(([v, t]) => h('option', { value: v }, t)));
    const check = (id, label, on) => h('label', { class: 'row' }, h('input', { type: 'checkbox', id, checked: on, onchange: () => this.applyDisplay() }), label);

    return h('aside', { class: 'panel' },
      h('h3', {}, 'Scenario'),
      h('div', { class: 'row' }, p.example,
        h('button', { type: 'button', onclick: () => p.file.click() }, 'Open…'),
        h('button', { type: 'button', id: 'save', onclick: () => downloadScenario(this.currentScenario(), 'scenario.json') }, 'Save'),
        h('button', { type: 'button', id: 'share', onclick: () => this.share() }, 'Share'), p.file),
      p.status,
      h('h3', {}, 'Simulation'),
      h('div', { class: 'row' }, p.playButton,
        h('button', { type: 'button', id: 'step', onclick: () => this.singleStep() }, 'Step'),
        h('button', { type: 'button', id: 'reset', onclick: () => this.reset() }, 'Reset'),
        h('button', { type: 'button', onclick: () => this.toggleHelp() }, '?')),
      h('div', { class: 'row' }, h('label', {}, 'speed', p.speed, p.speedOut)),
      h('h3', {}, 'Obstacles'),
      h('div', { class: 'palette' }, PALETTE.map((t, k) => h('button', { type: 'button', id: `add-${t}`, title: `add a ${t} (key ${(k + 1) % 10})`, onclick: () => this.addObstacle(t) }, t))),
      p.obstacles,
      p.selectedBox,
      h('h3', {}, 'Controller'),
      this.field('mode', p.mode), this.field('selection', p.selection),
      this.field('influence distance (m)', p.influenceDistance), this.field('repulsion gain', p.repulsionGain),
      this.field('max repulsion speed (m/s)', p.maxRepulsionSpeed), this.field('transition time (s/value)', p.transitionTime),
      p.controllerMessage,
      h('h3', {}, 'Sensing and dependability'),
      this.field('noise bound (m)', p.bound), this.field('noise σ (m)', p.sigma),
      this.field('switch window (s)', p.switchWindow), this.field('max switches', p.maxSwitches),
      this.field('on chattering', p.onChattering), this.field('lock time (s)', p.lockTime),
      h('div', { class: 'row' }, h('button', { type: 'button', id: 'apply-sensing', onclick: () => this.applySensing() }, 'Apply (restarts)')),
      p.worldMessage,
      h('h3', {}, 'Robot'),
      this.field('preset', p.preset),
      this.field('convention', p.convention),
      h('table', { class: 'dh', id: 'dh-table' },
        h('thead', {}, h('tr', {}, ['#', 'a', 'α', 'd', 'θ', 'type'].map((c) => h('th', {}, c)))), p.dh),
      h('div', { class: 'row' }, h('button', { type: 'button', id: 'apply-dh', onclick: () => this.applyDh() }, 'Apply DH table')),
      p.dhMessage,
      h('h3', {}, 'Initial joints'),
      p.joints,
      h('h3', {}, 'View'),
      this.field('camera', p.viewSelect),
      check('show-volumes', 'volumes', true), check('show-nodes', 'nodes', true), check('show-axes', 'frame axes', false));
  }

  // ---- start ----

  /** Loads the wasm, starts the viewer on `scenario` (an object or an example name). */
  async start(scenario) {
    this.wasm = await loadWasm();
    if (typeof this.wasm.World !== 'function') {
      throw new Error('This build of the library has no simulation (World): the page needs the avoidance module.');
    }
    const backend = this.options.backend ?? 'auto';
    const antialias = this.options.antialias ?? (backend !== 'webgl2' && (await softwareWebGpu()) ? false : undefined);
    this.viewer = await this.wasm.Viewer.create(this.canvas, { backend, view: this.options.view ?? 'auto', antialias });
    this.backend = this.viewer.backend;
    const resize = () => {
      const dpr = window.devicePixelRatio || 1;
      this.guard(() => this.viewer.resize(Math.max(1, Math.round(this.canvas.clientWidth * dpr)), Math.max(1, Math.round(this.canvas.clientHeight * dpr))));
    };
    resize();
    new ResizeObserver(resize).observe(this.canvas);
    this.wireInput();
    if (this.panel) {
      for (const name of this.wasm.exampleScenarioNames()) this.panel.example.append(h('option', { value: name }, name));
      this.panel.example.prepend(h('option', { value: '', disabled: true }, 'examples…'));
      this.panel.example.addEventListener('change', () => {
        const name = this.panel.example.value;
        if (name) this.loadScenario(this.wasm.exampleScenario(name), `example ${name}`);
      });
    }
    let initial = scenario;
    if (typeof scenario === 'string') {
      try {
        initial = this.wasm.exampleScenario(scenario);
      } catch (err) {
        throw new Error(`${errorText(err)} (examples: ${this.wasm.exampleScenarioNames().join(', ')})`);
      }
    }
    const failure = this.loadScenario(initial, typeof scenario === 'string' ? `example ${scenario}` : 'scenario');
    if (failure) throw new Error(failure);
    let first;
    const drawn = new Promise((resolve) => { first = resolve; });
    const frame = (now) => {
      if (this.destroyed) return;
      try {
        this.frame(now);
      } catch (err) {
        this.showError(`The playground stopped: ${errorText(err)}`);
        return;
      }
      if (this.frames === 2) first();
      requestAnimationFrame(frame);
    };
    requestAnimationFrame(frame);
    await drawn;
  }

  destroy() {
    this.destroyed = true;
    this.world?.free();
    this.viewer?.free();
    this.world = null;
    this.viewer = null;
  }

  // ---- scenario ----

  robotSpecOf(robot) {
    if (typeof robot === 'string') return this.wasm.robotPreset(robot);
    if (robot && typeof robot === 'object' && 'preset' in robot) return this.wasm.robotPreset(robot.preset);
    return robot;
  }

  /**
   * Replaces the scene with `scenario`. Returns `null`, or the error message
   * (shown in the widget) when the scenario is refused; the scene is then untouched.
   */
  loadScenario(scenario, label = 'scenario') {
    let world;
    let spec;
    let robotSet = false;
    try {
      if (scenario === null || typeof scenario !== 'object' || Array.isArray(scenario)) throw new Error('expected a scenario object');
      world = new this.wasm.World(scenario);
      spec = this.robotSpecOf(scenario.robot);
      robotSet = true;
      this.viewer.setRobot(spec);
    } catch (err) {
      world?.free();
      if (this.scenario && robotSet) {
        // Back to the current robot and its world in the view.
        this.guard(() => { this.viewer.setRobot(this.robotSpec); this.drawWorld(); });
      }
      const message = `The ${label} could not be loaded; the current scene is unchanged.\n${errorText(err)}`;
      this.showError(message);
      return message;
    }
    this.world?.free();
    this.world = world;
    this.scenario = clone(scenario);
    this.robotSpec = spec;
    this.selected = null;
    this.viewer.setSelected(null);
    this.afterRebuild();
    this.label = label;
    if (this.title) this.title.textContent = label;
    if (this.panel) {
      const name = label.startsWith('example ') ? label.slice('example '.length) : '';
      this.panel.example.value = [...this.panel.example.options].some((o) => o.value === name) ? name : '';
    }
    this.setStatus(`Loaded ${label}.`);
    this.errorBox.hidden = true;
    this.refreshPanel();
    return null;
  }

  /** Rebuilds the world from the current scenario with `changes` (fields replaced); keeps the old one on error. */
  rebuild(changes, messageBox) {
    const next = { ...this.currentScenario({ keepQ0: true }), ...changes };
    let world;
    try {
      world = new this.wasm.World(next);
    } catch (err) {
      const message = errorText(err);
      if (messageBox) messageBox.textContent = message;
      else this.showError(message);
      return false;
    }
    if (messageBox) messageBox.textContent = '';
    this.world.free();
    this.world = world;
    this.scenario = clone(next);
    this.afterRebuild();
    return true;
  }

  afterRebuild() {
    this.acc = 0;
    this.seenEvents = 0;
    for (const plot of Object.values(this.plots)) plot.clear();
    this.state = this.world.state();
    this.drawWorld();
    this.edited = true;
    this.notices.replaceChildren();
  }

  /**
   * The scene as a scenario. By default it is the scene as it is now: the
   * current joints become `q0` and every obstacle is where it is now (a
   * moving one continues its motion from there). With `asEdited`, `q0` and
   * the moving obstacles are those of the scenario as loaded and edited.
   */
  currentScenario({ keepQ0 = false, asEdited = keepQ0 } = {}) {
    const s = clone(this.scenario);
    const state = this.world.state();
    const shapes = new Map(state.obstacles.map((o) => [o.id, o.shape]));
    s.obstacles = (s.obstacles ?? []).map((o) => {
      const moving = o.motion && o.motion.type !== 'static';
      if (!shapes.has(o.id) || (moving && asEdited)) return o;
      let shape = clone(shapes.get(o.id));
      // A waypoint motion starts at its first point: start it from here.
      if (moving && o.motion.type === 'waypoints' && isPoint(o.motion.points?.[0])) shape = translateShape(shape, mul(o.motion.points[0], -1));
      return { ...o, shape };
    });
    if (!keepQ0) s.q0 = Array.from(state.q);
    return s;
  }

  async loadFile(file) {
    if (!file) return;
    try {
      const scenario = await readScenarioFile(file);
      this.loadScenario(scenario, `file "${file.name}"`);
    } catch (err) {
      this.showError(`${errorText(err)}\nThe current scene is unchanged.`);
    } finally {
      if (this.panel) this.panel.file.value = '';
    }
  }

  /** A URL that restores the current scene exactly. */
  shareUrl() {
    const url = new URL(location.href);
    url.hash = encodeShare(this.currentScenario());
    return url.href;
  }

  share() {
    const url = this.shareUrl();
    history.replaceState(null, '', url);
    this.lastHash = location.hash;
    navigator.clipboard?.writeText(url).then(
      () => this.setStatus('Link copied; it is also in the address bar.'),
      () => this.setStatus('The link is in the address bar.'),
    );
    this.setStatus('The link is in the address bar.');
    return url;
  }

  /** Loads the scenario carried by a URL fragment; returns false when there is none. */
  loadHash(hash) {
    let scenario;
    try {
      scenario = decodeShare(hash);
    } catch (err) {
      this.showError(`${errorText(err)}\nThe current scene is unchanged.`);
      return true;
    }
    if (!scenario) return false;
    this.loadScenario(scenario, 'shared scenario');
    return true;
  }

  // ---- edits ----

  guard(f, box) {
    try {
      const r = f();
      if (box) box.textContent = '';
      return r;
    } catch (err) {
      if (box) box.textContent = errorText(err);
      else this.showError(errorText(err));
      return undefined;
    }
  }

  setController(partial) {
    const box = this.panel?.controllerMessage;
    const ok = this.guard(() => { this.world.setController(partial); return true; }, box);
    if (ok) this.scenario.controller = { ...(this.scenario.controller ?? {}), ...partial };
  }

  applySensing() {
    const p = this.panel;
    const n = (input) => (input.value === '' ? undefined : Number(input.value));
    const noise = { bound: n(p.bound), sigma: n(p.sigma) };
    const sensing = { ...(this.scenario.sensing ?? {}) };
    if (noise.bound !== undefined || noise.sigma !== undefined) sensing.default = { ...(sensing.default ?? {}), ...clone(noise) };
    const dependability = { ...(this.scenario.dependability ?? {}), onChattering: p.onChattering.value };
    for (const key of ['switchWindow', 'maxSwitches', 'lockTime']) if (n(p[key]) !== undefined) dependability[key] = n(p[key]);
    if (this.rebuild({ sensing, dependability }, p.worldMessage)) this.setStatus('Sensing and dependability applied; the simulation restarted.');
  }

  setPreset(name) {
    if (name === 'custom') return;
    const spec = this.wasm.robotPreset(name);
    const dof = spec.joints.length;
    this.withRobot({ preset: name }, new Array(dof).fill(0), this.panel?.dhMessage);
  }

  /** Replaces the robot (and q0); keeps everything as it was on error. */
  withRobot(robot, q0, box) {
    const next = { ...this.currentScenario({ keepQ0: true }), robot, q0 };
    const message = this.loadScenario(next, this.label ?? 'scenario');
    if (message && box) {
      box.textContent = message;
      this.errorBox.hidden = true;
    }
    return !message;
  }

  applyDh() {
    const p = this.panel;
    const joints = [...p.dh.children].map((tr, i) => {
      const get = (k) => tr.querySelector(`[data-k="${k}"]`).value;
      const joint = { ...(this.robotSpec.joints[i] ?? {}) };
      for (const k of ['a', 'alpha', 'd', 'theta']) {
        const text = get(k).trim();
        joint[k] = text === '' ? NaN : Number(text);
      }
      joint.type = get('type');
      return joint;
    });
    const spec = { ...this.robotSpec, convention: p.convention.value, joints };
    const bad = [];
    joints.forEach((j, i) => ['a', 'alpha', 'd', 'theta'].forEach((k) => { if (!Number.isFinite(j[k])) bad.push(`joint ${i + 1}: ${k} is not a number`); }));
    if (bad.length) {
      p.dhMessage.textContent = bad.join('\n');
      return false;
    }
    const q0 = joints.map((_, i) => this.scenario.q0?.[i] ?? 0);
    if (this.withRobot(spec, q0, p.dhMessage)) {
      p.dhMessage.textContent = '';
      p.preset.value = 'custom';
      this.setStatus('DH table applied.');
      return true;
    }
    return false;
  }

  nextId(type) {
    const ids = new Set((this.scenario.obstacles ?? []).map((o) => o.id));
    for (let k = 1; ; k++) if (!ids.has(`${type}-${k}`)) return `${type}-${k}`;
  }

  /** Adds an obstacle of `type` in front of the arm; returns its id (or null). */
  addObstacle(type) {
    const nodes = this.state.skeleton.nodes;
    const base = nodes[0];
    const reach = Math.max(0.2, ...nodes.map((n) => len(sub(n, base))));
    const planar = nodes.every((n) => Math.abs(n[2] - base[2]) < 1e-9);
    const k = (this.scenario.obstacles ?? []).length;
    const c = add(base, [0.55 * reach, (0.35 - 0.18 * (k % 5)) * reach, planar ? 0 : 0.5 * reach]);
    const id = this.nextId(type);
    const spec = { id, shape: defaultShape(type, c, reach) };
    const ok = this.guard(() => { this.world.addObstacle(spec); return true; });
    if (!ok) return null;
    this.edited = true;
    this.scenario.obstacles = [...(this.scenario.obstacles ?? []), spec];
    this.select(id);
    this.setStatus(`Added ${id}.`);
    return id;
  }

  removeSelected() {
    const id = this.selected;
    if (!id) return;
    if (!this.guard(() => { this.world.removeObstacle(id); return true; })) return;
    this.edited = true;
    this.scenario.obstacles = this.scenario.obstacles.filter((o) => o.id !== id);
    this.select(null);
    this.setStatus(`Deleted ${id}.`);
  }

  shapeOf(id) {
    return this.world.state(this.world.eventCount).obstacles.find((o) => o.id === id)?.shape;
  }

  /** Replaces the shape of obstacle `id`; returns false (message shown) on error. */
  setShape(id, shape) {
    const ok = this.guard(() => { this.world.setObstacleShape(id, shape); return true; });
    if (!ok) return false;
    this.edited = true;
    this.scenario.obstacles = this.scenario.obstacles.map((o) => (o.id === id ? { ...o, shape: clone(shape) } : o));
    return true;
  }

  editSelected(f) {
    if (!this.selected) return;
    const shape = this.shapeOf(this.selected);
    if (shape && this.setShape(this.selected, f(shape))) this.refreshSelected();
  }

  select(id) {
    this.selected = id;
    this.viewer.setSelected(id);
    this.refreshObstacleList();
    this.refreshSelected();
  }

  // ---- simulation ----

  /**
   * Hands the world to the viewer: `drawWorld` reads it in Rust; a build
   * without it gets the state object read this frame (`drawState`).
   */
  drawWorld() {
    if (typeof this.viewer.drawWorld === 'function') this.viewer.drawWorld(this.world);
    else this.viewer.drawState(this.state ?? this.world.state());
  }

  toggleRun() {
    this.running = !this.running;
    if (this.playButton) this.playButton.textContent = this.running ? 'Pause' : 'Run';
  }

  singleStep() {
    if (this.running) this.toggleRun();
    this.pendingSteps += 1;
  }

  reset() {
    this.rebuild({});
    this.setStatus('Reset.');
  }

  frame(now) {
    const wall = this.lastNow === undefined ? 0 : (now - this.lastNow) / 1000;
    this.lastNow = now;
    const dt = this.scenario.dt;
    let steps = 0;
    const t0 = performance.now();
    if (this.running) {
      this.acc += Math.min(wall, 0.1) * this.speed;
      steps = Math.floor(this.acc / dt + 1e-9);
      const cap = Math.ceil(0.1 / dt);
      if (steps > cap) {
        steps = cap;
        this.acc = 0;
      } else {
        this.acc -= steps * dt;
      }
    } else {
      steps = this.pendingSteps;
    }
    this.pendingSteps = 0;
    // One call per frame where the binding offers it.
    if (steps > 0 && typeof this.world.advance === 'function') this.world.advance(dt, steps);
    else for (let i = 0; i < steps; i++) this.world.step(dt);
    const t1 = performance.now();
    // The viewer redraws only when something changed (a step, an edit, the camera).
    const changed = steps > 0 || this.edited;
    if (changed) {
      // Only the events not shown yet are copied out.
      this.state = this.world.state(this.seenEvents);
      this.drawWorld();
    }
    this.edited = false;
    this.viewer.render();
    const t2 = performance.now();
    this.frames += 1;

    this.frameTimes.push(now);
    if (this.frameTimes.length > 61) this.frameTimes.shift();
    const n = this.frameTimes.length - 1;
    const span = n > 0 ? this.frameTimes[n] - this.frameTimes[0] : 0;
    const k = 0.1;
    this.stats = {
      fps: span > 0 ? (1000 * n) / span : 0,
      frameMs: span > 0 ? span / n : 0,
      stepsPerFrame: steps,
      meanSteps: (this.stats.meanSteps ?? steps) * (1 - k) + steps * k,
      stepMs: (this.stats.stepMs ?? 0) * (1 - k) + (t1 - t0) * k,
      drawMs: (this.stats.drawMs ?? 0) * (1 - k) + (t2 - t1) * k,
      backend: this.backend,
    };
    if (steps > 0) this.record();
    if (changed) this.showEvents();
    // Plots and the text over the view are refreshed together, six times a
    // second: enough to read, and on software rendering every frame in
    // which anything but the 3D canvas changes costs a full composite.
    if (this.frames % REFRESH_EVERY === 0 || (!this.running && changed)) {
      for (const key of this.shownPlots) this.plots[key].draw();
      this.refreshHud();
    }
  }

  record() {
    const s = this.state;
    const t = s.t;
    this.plots.clearance.push('min', t, s.minClearance ?? NaN);
    // One line per obstacle (and per control point on it), so colours stay with their obstacle.
    const seen = new Map();
    for (const cp of s.controlPoints) {
      const k = (seen.get(cp.obstacle) ?? 0) + 1;
      seen.set(cp.obstacle, k);
      this.plots.clearance.push(k === 1 ? cp.obstacle : `${cp.obstacle} #${k}`, t, cp.distance);
    }
    const cp = s.controlPoints.find((c) => c.transitioning) ?? s.controlPoints[0];
    const joints = this.robotSpec?.joints ?? [];
    joints.forEach((j, i) => {
      let a = NaN;
      let d = NaN;
      if (cp) {
        const row = i + 1;
        a = row < cp.link ? j.a : row === cp.link ? cp.a : 0;
        d = row < cp.link ? j.d : row === cp.link ? cp.d : 0;
      }
      this.plots.dh.push(`a${i + 1}`, t, a);
      if (joints.some((x) => x.d !== 0)) this.plots.dh.push(`d${i + 1}`, t, d);
    });
    Array.from(s.qdot ?? []).forEach((v, i) => this.plots.qdot.push(`q̇${i + 1}`, t, v));

  }

  showEvents() {
    // `state(since)` returns the events from index `since` on (a binding
    // without the cursor returns them all).
    let events = this.state.events ?? [];
    const total = typeof this.world.eventCount === 'number' ? this.world.eventCount : events.length;
    if (events.length === total) events = events.slice(this.seenEvents);
    for (const e of events) {
      const text = `t = ${Number(e.t).toFixed(3)} s · ${EVENT_TEXT[e.kind] ?? e.kind}`;
      const note = h('div', { class: `notice ${e.kind}` }, text);
      this.notices.append(note);
      while (this.notices.children.length > 4) this.notices.firstChild.remove();
      setTimeout(() => note.remove(), e.kind === 'stop' ? 8000 : 3500);
    }
    this.seenEvents = total;
  }

  refreshHud() {
    const s = this.state;
    const st = this.stats;
    this.statsBox.textContent = `${st.fps.toFixed(0)} fps  ${st.frameMs.toFixed(1)} ms/frame\n`
      + `${st.stepsPerFrame} steps/frame (${(1 / this.scenario.dt).toFixed(0)} Hz × ${this.speed.toFixed(2)})\n`
      + `step ${st.stepMs.toFixed(2)} ms  draw ${st.drawMs.toFixed(2)} ms  ${this.backend === 'webgpu' ? 'WebGPU' : 'WebGL2'}`;
    const ttc = s.timeToCollision;
    const lines = [
      `t ${s.t.toFixed(3)} s${s.stopped ? '  STOPPED' : this.running ? '' : '  paused'}`,
      `min clearance ${Number.isFinite(s.minClearance) ? `${(s.minClearance * 1000).toFixed(0)} mm` : '—'}`,
      `time to collision ${ttc === undefined || ttc === null || !Number.isFinite(ttc) ? '—' : `${ttc.toFixed(2)} s`}`,
    ];
    s.controlPoints.slice(0, 3).forEach((cp, i) => {
      let text = `cp${i + 1} link ${cp.link}  d' ${cp.d.toFixed(3)}  a' ${cp.a.toFixed(3)} m`;
      if (cp.transitioning && cp.target) text += `  → link ${cp.target.link} (${cp.target.d.toFixed(3)}, ${cp.target.a.toFixed(3)})`;
      lines.push(text);
    });
    this.hud.textContent = lines.join('\n');
  }

  // ---- panel refresh ----

  setStatus(text) {
    if (this.panel) this.panel.status.textContent = text;
  }

  showError(message) {
    this.errorMessage.textContent = message;
    this.errorBox.hidden = false;
  }

  applyDisplay() {
    const get = (id) => this.root.getElementById?.(id)?.checked ?? this.root.querySelector(`#${id}`)?.checked;
    this.guard(() => this.viewer.setDisplay({ volumes: get('show-volumes'), nodes: get('show-nodes'), axes: get('show-axes'), grid: true }));
  }

  refreshPanel() {
    const p = this.panel;
    if (!p) return;
    const s = this.scenario;
    const preset = typeof s.robot === 'object' && 'preset' in s.robot ? s.robot.preset : 'custom';
    p.preset.value = preset;
    p.convention.value = this.robotSpec.convention ?? 'standard';
    p.dh.replaceChildren(...this.robotSpec.joints.map((j, i) => h('tr', {},
      h('td', {}, String(i + 1)),
      ['a', 'alpha', 'd', 'theta'].map((k) => h('td', {}, h('input', { 'data-k': k, id: `dh-${i}-${k}`, value: String(j[k] ?? 0), 'aria-label': `joint ${i + 1} ${k}`,
        oninput: () => this.validateDh() }))),
      h('td', {}, h('select', { 'data-k': 'type', 'aria-label': `joint ${i + 1} type` },
        ['revolute', 'prismatic'].map((t) => h('option', { value: t, selected: (j.type ?? 'revolute') === t }, t)))))));
    p.dhMessage.textContent = '';
    const c = s.controller ?? {};
    p.mode.value = c.mode ?? 'velocity';
    p.selection.value = c.selection ?? 'pairs';
    for (const key of ['influenceDistance', 'repulsionGain', 'maxRepulsionSpeed', 'transitionTime']) p[key].value = c[key] ?? '';
    const noise = s.sensing?.default ?? {};
    p.bound.value = noise.bound ?? '';
    p.sigma.value = noise.sigma ?? '';
    const dep = s.dependability ?? {};
    for (const key of ['switchWindow', 'maxSwitches', 'lockTime']) p[key].value = dep[key] ?? '';
    p.onChattering.value = dep.onChattering ?? 'stop';
    p.controllerMessage.textContent = '';
    p.worldMessage.textContent = '';
    this.buildJointSliders();
    this.refreshObstacleList();
    this.refreshSelected();
  }

  validateDh() {
    const p = this.panel;
    const problems = [];
    [...p.dh.children].forEach((tr, i) => {
      for (const input of tr.querySelectorAll('input')) {
        const text = input.value.trim();
        const bad = text === '' || !Number.isFinite(Number(text));
        input.setAttribute('aria-invalid', bad ? 'true' : 'false');
        input.style.background = bad ? '#fff1f0' : '';
        if (bad) problems.push(`joint ${i + 1}: ${input.dataset.k} must be a number (got "${text}")`);
      }
    });
    p.dhMessage.textContent = problems.join('\n');
  }

  buildJointSliders() {
    const p = this.panel;
    const q0 = this.scenario.q0 ?? [];
    p.joints.replaceChildren(...this.robotSpec.joints.map((j, i) => {
      const lo = Number.isFinite(j.min) ? j.min : -Math.PI;
      const hi = Number.isFinite(j.max) ? j.max : Math.PI;
      const value = q0[i] ?? 0;
      const out = h('output', {}, value.toFixed(2));
      const slider = h('input', { type: 'range', id: `joint-${i}`, min: String(lo), max: String(hi), step: '0.01', value: String(value), 'aria-label': `initial joint ${i + 1}` });
      slider.addEventListener('input', () => {
        const q = this.robotSpec.joints.map((_, k) => this.scenario.q0?.[k] ?? 0);
        q[i] = Number(slider.value);
        out.textContent = q[i].toFixed(2);
        this.rebuild({ q0: q }, p.worldMessage);
      });
      return h('div', { class: 'row' }, h('label', {}, `q${i + 1}`, slider, out));
    }));
  }

  refreshObstacleList() {
    const p = this.panel;
    if (!p) return;
    p.obstacles.replaceChildren(...(this.scenario.obstacles ?? []).map((o) => h('li', {
      class: o.id === this.selected ? 'selected' : '',
      onclick: () => this.select(o.id),
    }, `${o.id} · ${o.shape?.type ?? '?'}${o.motion && o.motion.type !== 'static' ? ` · ${o.motion.type}` : ''}`)));
  }

  refreshSelected() {
    const p = this.panel;
    if (!p) return;
    if (!this.selected) {
      p.selectedBox.replaceChildren(h('p', { class: 'hint' }, 'Click an obstacle to select it; drag to move it (Alt: along the view direction).'));
      return;
    }
    const shape = this.shapeOf(this.selected);
    if (!shape) {
      p.selectedBox.replaceChildren();
      return;
    }
    const c = shapeCenter(shape);
    const coords = c.map((x, k) => h('input', { type: 'number', step: '0.01', value: x.toFixed(3), style: 'width: 4.6rem', 'aria-label': `position ${'xyz'[k]}`, id: `pos-${'xyz'[k]}`,
      onchange: (e) => {
        const v = Number(e.target.value);
        if (!Number.isFinite(v)) return;
        const delta = [0, 0, 0];
        delta[k] = v - c[k];
        this.editSelected((s) => translateShape(s, delta));
      } }));
    const btn = (label, title, f) => h('button', { type: 'button', title, onclick: () => this.editSelected(f) }, label);
    const z = [0, 0, 1];
    const x = [1, 0, 0];
    p.selectedBox.replaceChildren(
      h('div', { class: 'row' }, h('strong', {}, this.selected), h('button', { type: 'button', id: 'delete', onclick: () => this.removeSelected() }, 'Delete')),
      h('div', { class: 'row' }, 'centre', ...coords),
      h('div', { class: 'row' }, 'size', btn('−', 'shrink', (s) => scaleShape(s, 0.8)), btn('+', 'grow', (s) => scaleShape(s, 1.25)),
        'rotate z', btn('⟲', 'rotate +15° about z', (s) => rotateShape(s, z, Math.PI / 12)), btn('⟳', 'rotate −15° about z', (s) => rotateShape(s, z, -Math.PI / 12)),
        'x', btn('⟲', 'rotate +15° about x', (s) => rotateShape(s, x, Math.PI / 12))),
      h('pre', { class: 'hint', id: 'shape-json', style: 'white-space: pre-wrap; margin: 0.2rem 0;' }, JSON.stringify(shape, (k, v) => (typeof v === 'number' ? Number(v.toFixed(4)) : v))),
    );
  }

  toggleHelp(show) {
    this.helpBox.hidden = show === undefined ? !this.helpBox.hidden : !show;
  }

  // ---- input ----

  /** Canvas pixel (drawing buffer) of a pointer event. */
  pixel(e) {
    const r = this.canvas.getBoundingClientRect();
    const dpr = window.devicePixelRatio || 1;
    return [(e.clientX - r.left) * dpr, (e.clientY - r.top) * dpr];
  }

  /** Where the ray through pixel `px` meets the plane through `p0` with normal `n`. */
  onPlane(px, p0, n) {
    const ray = this.viewer.rayAt(px[0], px[1]);
    const denom = dot(ray.direction, n);
    if (Math.abs(denom) < 1e-9) return null;
    const s = dot(sub(p0, ray.origin), n) / denom;
    return add(ray.origin, mul(ray.direction, s));
  }

  wireInput() {
    const canvas = this.canvas;
    let drag = null;
    canvas.addEventListener('contextmenu', (e) => e.preventDefault());
    canvas.addEventListener('pointerdown', (e) => {
      canvas.focus();
      canvas.setPointerCapture(e.pointerId);
      const px = this.pixel(e);
      const camera = e.button === 2 || e.button === 1 || e.shiftKey;
      if (!camera && e.button === 0) {
        const ray = this.viewer.rayAt(px[0], px[1]);
        const hit = this.guard(() => this.world.pick(ray.origin, ray.direction));
        if (hit) {
          this.select(hit.id);
          const n = this.viewer.viewDirection();
          const shape = this.shapeOf(hit.id);
          // Metres per pixel at the picked point, for moves along the normal.
          const a = this.onPlane(px, hit.point, n);
          const b = this.onPlane([px[0], px[1] + 1], hit.point, n);
          // The drag plane faces the camera through the picked point; the
          // anchor is where the pointer's ray meets it.
          drag = { kind: 'obstacle', id: hit.id, shape, point: a ?? hit.point, n, along: e.altKey || e.ctrlKey || e.metaKey,
            y: px[1], mpp: a && b ? len(sub(a, b)) : 0.002, moved: false };
          return;
        }
      }
      drag = { kind: 'camera', x: e.clientX, y: e.clientY, pan: camera, moved: false };
    });
    const dragTo = (e) => {
      if (!drag) return;
      if (drag.kind === 'camera') {
        const dpr = window.devicePixelRatio || 1;
        const dx = (e.clientX - drag.x) * dpr;
        const dy = (e.clientY - drag.y) * dpr;
        drag.x = e.clientX;
        drag.y = e.clientY;
        if (dx || dy) drag.moved = true;
        if (drag.pan || this.viewer.view !== '3d') this.viewer.pan(dx, dy);
        else this.viewer.orbit(dx, dy);
        return;
      }
      const px = this.pixel(e);
      const along = e.altKey || e.ctrlKey || e.metaKey;
      let delta;
      if (along) {
        delta = mul(drag.n, (px[1] - drag.y) * drag.mpp);
      } else {
        const p = this.onPlane(px, drag.point, drag.n);
        if (!p) return;
        delta = sub(p, drag.point);
      }
      drag.y = px[1];
      if (len(delta) === 0) return;
      drag.point = add(drag.point, delta);
      drag.shape = translateShape(drag.shape, delta);
      drag.moved = true;
      if (!this.setShape(drag.id, drag.shape)) drag = null;
    };
    canvas.addEventListener('pointermove', dragTo);
    const end = (e) => {
      // The browser may coalesce the last moves into the release: apply it.
      if (e.type === 'pointerup') dragTo(e);
      if (drag?.kind === 'camera' && !drag.moved && !drag.pan) this.select(null);
      if (drag?.kind === 'obstacle') this.refreshSelected();
      drag = null;
    };
    canvas.addEventListener('pointerup', end);
    canvas.addEventListener('pointercancel', end);
    canvas.addEventListener('wheel', (e) => {
      e.preventDefault();
      this.viewer.zoom(Math.exp(e.deltaY * 0.001));
    }, { passive: false });
    const keys = this.options.keyboardTarget ?? this.container;
    keys.addEventListener('keydown', (e) => this.onKey(e));
  }

  onKey(e) {
    const t = e.composedPath?.()[0] ?? e.target;
    if (t && ['INPUT', 'SELECT', 'TEXTAREA'].includes(t.tagName)) return;
    if (e.ctrlKey || e.metaKey) return;
    const views = ['3d', 'top', 'front', 'side'];
    const handled = (() => {
      switch (e.key) {
        case ' ': this.toggleRun(); return true;
        case 's': case 'S': case '.': this.singleStep(); return true;
        case 'r': case 'R': this.reset(); return true;
        case 'Delete': case 'Backspace': this.removeSelected(); return true;
        case 'Escape': this.toggleHelp(false); this.select(null); return true;
        case '?': case 'h': case 'H': this.toggleHelp(); return true;
        case '[': this.editSelected((s) => scaleShape(s, 0.8)); return true;
        case ']': this.editSelected((s) => scaleShape(s, 1.25)); return true;
        case 'q': case 'Q': this.editSelected((s) => rotateShape(s, [0, 0, 1], Math.PI / 12)); return true;
        case 'e': case 'E': this.editSelected((s) => rotateShape(s, [0, 0, 1], -Math.PI / 12)); return true;
        case 'v': case 'V': {
          const next = views[(views.indexOf(this.viewer.view) + 1) % views.length];
          this.viewer.setView(next);
          if (this.panel) this.panel.viewSelect.value = next;
          return true;
        }
        default: {
          const k = '1234567890'.indexOf(e.key);
          if (k >= 0 && this.controls === 'full') {
            this.addObstacle(PALETTE[k]);
            return true;
          }
          return false;
        }
      }
    })();
    if (handled) e.preventDefault();
  }

  // ---- test hook ----

  /** A snapshot: the world's state, the viewer's, the frame counter and stats. */
  snapshot() {
    if (!this.viewer) return { backend: null, frames: this.frames };
    const world = this.world.state();
    return { ...this.viewer.state(), q: Array.from(world.q), world, frames: this.frames, stats: { ...this.stats }, selected: this.selected, running: this.running, speed: this.speed };
  }
}
