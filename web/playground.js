// The playground widget: a simulated world (the library's `World`) drawn by
// the wgpu `Viewer`, with the panel, plots, picking and dragging, scenarios
// and the stats overlay. `web/embed.js` wraps it as <skeleton-playground>;
// the full page is one such element filling the window.
//
// Everything the person types or loads is shown with textContent, never as
// HTML. Every failure is shown in the widget and leaves the scene as it was.
import { clone, errorText, h } from './dom.js';
import { EventFeed } from './events.js';
import { TraceRecorder } from './export.js';
import { wireInput } from './input.js';
import { readoutMethods } from './readouts.js';
import { sceneMethods } from './scene-edits.js';
import { urdfMethods } from './urdf-files.js';
import { presetMeshMethods } from './preset-meshes.js';
import { pinMethods, withoutPins } from './pinning.js';
import { PRESETS, applyDh, buildPanel, fillPresets, refreshObstacleList, refreshPanel, refreshSelected, robotRows } from './panel.js';
import { TimePlot } from './plots.js';
import { armPoints, followStats, placeNotices } from './notice-place.js';
import { PALETTE, defaultShape, rotateShape, scaleShape, shapeCenter, translateShape, useLibrary } from './shapes.js';
import { STYLE } from './style.js';
import { loadWasm } from './wasm.js';

export { loadWasm };
export { PALETTE, PRESETS, defaultShape, rotateShape, scaleShape, shapeCenter, translateShape, useLibrary };

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

// ---- the widget ----

const HELP = [
  ['Space', 'pause / run'],
  ['S or .', 'single control step (while paused)'],
  ['R', 'reset the simulation and the view'],
  ['F or double click', 'frame the robot and the obstacles'],
  ['1 … 0', 'add point, segment, sphere, capsule, plane, rectangle, disk, polygon, box, human'],
  ['Click', 'select an obstacle (drag it on the plane facing you)'],
  ['P, then click the arm', 'pin a control point on the link clicked (selection: pinned)'],
  ['Alt + drag', 'move the obstacle along the view direction'],
  ['Delete', 'delete the selected obstacle'],
  ['[ / ]', 'shrink / grow the selected obstacle'],
  ['Q / E', 'rotate the selected obstacle about z'],
  ['Escape', 'deselect, leave Pin mode, close this help'],
  ['V', 'next camera view'],
  ['Drag empty space', 'orbit (3D) or pan (2D); right or Shift + drag pans'],
  ['Wheel', 'zoom once the view was clicked (or with Ctrl held); two fingers pinch'],
  ['?', 'this help'],
];

/** Frames between refreshes of the plots and the text over the view. */
const REFRESH_EVERY = 10;

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
    /** Whether the wheel zooms without Ctrl (the view was clicked; always on the full page). */
    this.engaged = options.captureWheel ?? false;
    this.offscreen = false;
    this.build();
  }

  // ---- DOM ----

  build() {
    const style = h('style', {}, STYLE);
    this.canvas = h('canvas', { class: 'view', id: 'view', tabindex: '0', role: 'img',
      'aria-label': 'Simulated robot and obstacles. Drag to orbit, click an obstacle to select it; press ? for the keys.' });
    this.hintBox = h('div', { class: 'hint-box', id: 'view-hint', hidden: true, 'aria-live': 'polite' });
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
    const stage = h('div', { class: 'stage' }, this.canvas, this.statsBox, this.hud, this.notices, this.hintBox, this.errorBox, this.helpBox);
    followStats(stage, this.statsBox);
    // A folder, a zip or files holding a URDF and its meshes, dropped on the view.
    stage.addEventListener('dragover', (e) => e.preventDefault());
    stage.addEventListener('drop', (e) => this.dropUrdf(e));
    if (this.controls === 'full') {
      stage.append(h('button', { type: 'button', class: 'panel-toggle', id: 'panel-toggle', 'aria-controls': 'panel', 'aria-expanded': 'false',
        onclick: (e) => e.currentTarget.setAttribute('aria-expanded', String(this.container.classList.toggle('panel-open'))) }, '☰ Controls'));
    }

    this.plots = {
      clearance: new TimePlot(h('canvas', { id: 'plot-clearance' }), { title: 'clearance', unit: 'm', min: 0 }),
      dh: new TimePlot(h('canvas', { id: 'plot-dh' }), { title: 'control point DH values', unit: 'm' }),
      qdot: new TimePlot(h('canvas', { id: 'plot-qdot' }), { title: 'joint velocities', unit: 'rad/s' }),
    };
    const wanted = this.controls === 'full' ? Object.keys(this.plots) : (this.options.plot ? [this.options.plot] : []);
    this.shownPlots = wanted.filter((k) => this.plots[k]);
    const plots = h('div', { class: 'plots' }, this.shownPlots.map((k) => this.plots[k].element));
    const log = this.controls === 'full' ? h('section', { class: 'log', id: 'log', 'aria-label': 'event log' }) : null;
    if (log) plots.append(log);
    // Notices go to the corner of the view that hides the least of the arm.
    const place = () => this.viewer && placeNotices(this.notices, this.canvas, armPoints(this.guard(() => this.viewer.state())?.screenNodes, window.devicePixelRatio || 1));
    this.events = new EventFeed({ notices: this.notices, log, onSeek: (t) => this.seek(t), onNotices: place });
    this.trace = new TraceRecorder();

    const cls = `sp ${this.controls}${this.options.plot ? ' with-plot' : ''}${this.options.stats ? ' with-stats' : ''}`;
    this.container = h('div', { class: cls }, stage, plots);
    if (this.controls === 'full') this.container.append(buildPanel(this));
    else if (this.controls === 'minimal') this.container.append(this.buildBar());
    this.root.append(style, this.container);
  }

  buildBar() {
    this.title = h('span', { class: 'title' });
    this.playButton = h('button', { type: 'button', onclick: () => this.toggleRun() }, 'Pause');
    return h('div', { class: 'bar' },
      this.playButton,
      h('button', { type: 'button', onclick: () => this.reset(), title: 'restart and frame the view' }, 'Reset'),
      h('button', { type: 'button', onclick: () => this.fit(), title: 'frame the robot and the obstacles (F, double click)' }, 'Fit'),
      this.title);
  }

  // ---- start ----

  /** Loads the wasm, starts the viewer on `scenario` (an object or an example name). */
  async start(scenario) {
    this.wasm = await loadWasm();
    useLibrary(this.wasm);
    if (typeof this.wasm.World !== 'function') {
      throw new Error('This build of the library has no simulation (World): the page needs the avoidance module.');
    }
    const backend = this.options.backend ?? 'auto';
    const antialias = this.options.antialias ?? (backend !== 'webgl2' && (await softwareWebGpu()) ? false : undefined);
    // The element owns its canvas: drawn through its OffscreenCanvas, which the
    // browser composites more cheaply (render/gpu.rs).
    this.viewer = await this.wasm.Viewer.create(this.canvas, { backend, view: this.options.view ?? 'auto', antialias, offscreen: true });
    this.backend = this.viewer.backend;
    const resize = () => {
      const dpr = window.devicePixelRatio || 1;
      this.guard(() => this.viewer.resize(Math.max(1, Math.round(this.canvas.clientWidth * dpr)), Math.max(1, Math.round(this.canvas.clientHeight * dpr))));
    };
    resize();
    new ResizeObserver(() => {
      resize();
      // A view the person has not moved follows the widget's size.
      if (!this.cameraTouched) this.fit();
    }).observe(this.canvas);
    wireInput(this);
    if (this.panel) {
      // The library names its presets; the page does not keep its own list.
      if (typeof this.wasm.presetNames === 'function') fillPresets(this.panel, this.wasm.presetNames());
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
      // The direction and the points the scenario asks to be seen from
      // (checked with the world above); `fit` below applies the points.
      if (scenario.camera) this.viewer.setCamera(scenario.camera);
    } catch (err) {
      world?.free();
      if (this.scenario && robotSet) {
        // Back to the current robot, its camera and its world in the view.
        this.guard(() => {
          this.viewer.setRobot(this.robotSpec);
          if (this.scenario.camera) this.viewer.setCamera(this.scenario.camera);
          this.drawWorld();
        });
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
    this.previousLabel = this.label;
    this.label = label;
    if (this.title) this.title.textContent = label;
    if (this.panel) {
      const name = label.startsWith('example ') ? label.slice('example '.length) : '';
      this.panel.example.value = [...this.panel.example.options].some((o) => o.value === name) ? name : '';
    }
    this.setStatus(`Loaded ${label}.`);
    this.errorBox.hidden = true;
    this.refreshPanel();
    this.fit();
    if (label !== 'shared scenario') this.forgetShareLink();
    this.showPresetMeshes();
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
    this.forgetShareLink();
    return true;
  }

  afterRebuild() {
    this.acc = 0;
    this.seenEvents = 0;
    for (const plot of Object.values(this.plots)) plot.clear();
    this.state = this.world.state();
    this.drawWorld();
    this.edited = true;
    this.events.clear();
    this.trace.clear();
    this.plots.clearance.setReferences([{ v: this.influence(), label: 'influence distance' }]);
    const speeds = robotRows(this.robotSpec).map((r) => r.joint.maxVelocity).filter(Number.isFinite);
    const vmax = speeds.length ? Math.min(...speeds) : NaN;
    this.plots.qdot.setReferences([{ v: vmax, label: 'lowest speed limit' }, { v: -vmax }]);
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
    if (ok) {
      this.scenario.controller = { ...(this.scenario.controller ?? {}), ...partial };
      this.forgetShareLink();
      this.refreshPinned();
    } else if (this.panel) {
      // Refused: the menus show what is in force.
      const c = this.scenario.controller ?? {};
      this.panel.mode.value = c.mode ?? 'velocity';
      this.panel.selection.value = c.selection ?? 'perObstacle';
    }
    return Boolean(ok);
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
    const dof = robotRows(this.wasm.robotPreset(name)).length;
    this.withRobot({ preset: name }, new Array(dof).fill(0), this.panel?.dhMessage, `robot preset ${name}`);
  }

  /**
   * Replaces the robot (and q0); keeps everything as it was on error, with a
   * message naming `what` (the preset or the edited robot the person chose).
   */
  withRobot(robot, q0, box, what = 'robot') {
    // Pinned points name rows of the old robot: a new robot starts without them.
    const current = this.currentScenario({ keepQ0: true });
    const next = { ...current, robot, q0, controller: withoutPins(current.controller) };
    const message = this.loadScenario(next, what);
    if (!message) {
      // The scene keeps its name; only the robot changed.
      this.label = this.previousLabel ?? what;
      if (this.title) this.title.textContent = this.label;
    }
    if (message && box) {
      box.textContent = message;
      this.errorBox.hidden = true;
    }
    return !message;
  }

  applyDh() {
    return applyDh(this);
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
    this.fit();
    this.setStatus('Reset.');
  }

  /** How many control steps this frame owes the simulation (real time × speed, capped). */
  stepsDue(wall) {
    const dt = this.scenario.dt;
    if (!this.running || this.offscreen) return this.pendingSteps;
    // A frame longer than 100 ms (a busy machine, a background tab) does
    // not make the simulation race to catch up: the excess is dropped, and
    // counted (`droppedS`), so that real time is kept or the loss is known.
    // `wallS`: the page's own clock (frame timestamps × speed) while it
    // runs; simulated time plus `droppedS` follows it to within a step.
    this.wallS = (this.wallS ?? 0) + wall * this.speed;
    this.droppedS = (this.droppedS ?? 0) + Math.max(0, wall - 0.1) * this.speed;
    this.acc += Math.min(wall, 0.1) * this.speed;
    let steps = Math.floor(this.acc / dt + 1e-9);
    const cap = Math.ceil(0.1 / dt);
    if (steps > cap) {
      steps = cap;
      this.droppedS += this.acc - cap * dt;
      this.acc = 0;
    } else {
      this.acc -= steps * dt;
    }
    return steps;
  }

  frame(now) {
    const wall = this.lastNow === undefined ? 0 : (now - this.lastNow) / 1000;
    this.lastNow = now;
    const dt = this.scenario.dt;
    const t0 = performance.now();
    const steps = this.stepsDue(wall);
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
    this.measure(now, steps, t1 - t0, t2 - t1);
    if (steps > 0) this.record();
    if (changed) this.showEvents();
    // Plots, the text over the view and the event feed are refreshed
    // together, six times a second: enough to read, and on software
    // rendering every frame in which anything but the 3D canvas changes
    // costs a full composite (a stop is shown at once: EventFeed.queue).
    if (this.frames % REFRESH_EVERY === 0 || (!this.running && changed) || this.seekPending) {
      this.seekPending = false;
      for (const key of this.shownPlots) this.plots[key].draw();
      this.refreshHud();
      this.events.flush();
    }
  }

  measure(now, steps, stepMs, drawMs) {
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
      stepMs: (this.stats.stepMs ?? 0) * (1 - k) + stepMs * k,
      drawMs: (this.stats.drawMs ?? 0) * (1 - k) + drawMs * k,
      droppedS: this.droppedS ?? 0,
      wallS: this.wallS ?? 0,
      backend: this.backend,
    };
  }

  // ---- camera ----

  /** Frames the robot and the obstacles near it (about 60 % of the view). */
  fit() {
    if (!this.viewer) return;
    // A portrait view (a phone) is limited by its width: fill more of it.
    const portrait = this.canvas.clientHeight > 1.2 * this.canvas.clientWidth;
    this.guard(() => this.viewer.fit?.(portrait ? 0.9 : 0.85, this.overlayTop()));
    this.cameraTouched = false;
    this.edited = true;
  }

  /**
   * Drawing-buffer pixels at the top of the view covered by the stats and
   * the HUD (and a small margin): a fit frames the scene below them.
   */
  overlayTop() {
    const top = this.canvas.getBoundingClientRect().top;
    const bottoms = [this.statsBox, this.hud].filter((e) => e && !e.hidden && e.offsetParent !== null)
      .map((e) => e.getBoundingClientRect().bottom - top + (e === this.hud ? this.hudGrowth() : 0));
    const covered = bottoms.length ? Math.max(0, ...bottoms) + 6 : 0;
    return covered * (window.devicePixelRatio || 1);
  }

  /** The person moved the camera: the view stops following resizes. */
  cameraMoved() {
    this.cameraTouched = true;
  }

  /** A short hint over the view (e.g. how to zoom), hidden after a while. */
  hint(text) {
    this.hintBox.textContent = text;
    this.hintBox.hidden = false;
    clearTimeout(this.hintTimer);
    this.hintTimer = setTimeout(() => { this.hintBox.hidden = true; }, 1800);
  }

  /** Off screen the simulation waits (an IntersectionObserver tells). */
  setOffscreen(offscreen) {
    this.offscreen = offscreen;
    this.lastNow = undefined;
  }

  /** Downloads the run so far: `format` is `"csv"` or `"json"`. */
  exportTrace(format) {
    const names = robotRows(this.robotSpec).map((r) => r.label);
    this.trace.download(format, names, this.label ?? 'run');
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
    this.guard(() => this.viewer.setDisplay({ meshes: get('show-meshes') ?? true, volumes: get('show-volumes'), nodes: get('show-nodes'), axes: get('show-axes'), grid: true }));
  }

  refreshPanel() {
    refreshPanel(this);
  }

  refreshObstacleList() {
    refreshObstacleList(this);
  }

  refreshSelected() {
    refreshSelected(this);
  }

  toggleHelp(show) {
    this.helpBox.hidden = show === undefined ? !this.helpBox.hidden : !show;
  }

  // ---- test hook ----

  /** A snapshot: the world's state, the viewer's, the frame counter and stats. */
  snapshot() {
    if (!this.viewer) return { backend: null, frames: this.frames };
    const world = this.world.state();
    return { ...this.viewer.state(), q: Array.from(world.q), world, frames: this.frames, stats: { ...this.stats }, selected: this.selected, running: this.running, speed: this.speed,
      events: this.events.snapshot(), offscreen: Boolean(this.offscreen), engaged: Boolean(this.engaged) };
  }
}

Object.assign(Playground.prototype, sceneMethods, readoutMethods, pinMethods, urdfMethods, presetMeshMethods);
