// The playground widget: a simulated world (the library's `World`) drawn by
// the wgpu `Viewer`, with the panel, plots, picking and dragging, scenarios
// and the stats overlay. `web/embed.js` wraps it as <skeleton-playground>;
// the full page is one such element filling the window.
//
// The Playground is the one owner of the widget's parts; each part owns its
// state and gets a narrow interface from here (its comment says which):
//
// | part | file | owns |
// |---|---|---|
// | `Sim` | sim.js | the world, the scenario, the robot spec, the last state |
// | `Messages` | messages.js | the error box, the hint, the status line |
// | `SceneEdits` | scene-edits.js | the selection; obstacles added, moved, deleted |
// | `SceneLinks` | share.js | *Open…*, *Share*, `#scenario=` links |
// | `Pinning` | pinning.js | Pin mode and the pinned points' section |
// | `UrdfLoading` | urdf-files.js | URDF folders, zips and files; the fit's report |
// | `PresetMeshes` | preset-meshes.js | the presets' meshes, fetched once |
// | `Readouts` | readouts.js | the HUD, the stats overlay and its figures |
// | `PlotStrip` | plot-strip.js | the plots |
// | `EventFeed` | events.js | notices and the event log |
// | `TraceRecorder` | export.js | the run so far, for *trace CSV / JSON* |
// | `Panel` | panel.js | the side panel's controls |
// | `LiveInput` | camera.js | the camera, the sensor bridge, the live person's frames |
// | `FrameLoop` | loop.js | stepping (`SimClock`, clock.js), drawing, feeding the readouts |
// | `WidgetFrame` | frame.js | the view's overlays, the help, the bar |
// | input | input.js | pointer, wheel, touch and keys of the view |
//
// Everything the person types or loads is shown with textContent, never as
// HTML. Every failure is shown in the widget and leaves the scene as it was.
import { errorText, h } from './dom.js';
import { EventFeed } from './events.js';
import { TraceRecorder } from './export.js';
import { wireInput } from './input.js';
import { Readouts } from './readouts.js';
import { SceneEdits } from './scene-edits.js';
import { SceneLinks } from './share.js';
import { UrdfLoading } from './urdf-files.js';
import { PresetMeshes } from './preset-meshes.js';
import { Pinning, withoutPins } from './pinning.js';
import { PRESETS, Panel, fillPresets, robotRows } from './panel.js';
import { buildDependability, refreshDependability } from './dependability.js';
import { PlotStrip } from './plot-strip.js';
import { Messages } from './messages.js';
import { Sim } from './sim.js';
import { FrameLoop } from './loop.js';
import { armPoints, placeNotices } from './notice-place.js';
import { PALETTE, defaultShape, rotateShape, scaleShape, shapeCenter, translateShape, useLibrary } from './shapes.js';
import { WidgetFrame, softwareWebGpu } from './frame.js';
import { loadWasm } from './wasm.js';
import { LiveInput } from './camera.js';

export { loadWasm };
export { PALETTE, PRESETS, defaultShape, rotateShape, scaleShape, shapeCenter, translateShape, useLibrary };

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
    this.viewer = null;
    /** Whether the wheel zooms without Ctrl (the view was clicked; always on the full page). */
    this.engaged = options.captureWheel ?? false;
    this.offscreen = false;
    this.sim = new Sim();
    this.trace = new TraceRecorder();
    this.canvas = h('canvas', { class: 'view', id: 'view', tabindex: '0', role: 'img',
      'aria-label': 'Simulated robot and obstacles. Drag to orbit, click an obstacle to select it; press ? for the keys.' });
    this.makeParts();
    this.build();
  }

  /** The parts, each with the narrow interface it needs. */
  makeParts() {
    const sim = this.sim;
    const viewer = () => this.viewer;
    const messages = new Messages({ statusBox: () => this.panelPart?.el.status ?? null });
    const load = (scenario, label) => this.loadScenario(scenario, label);
    const changed = () => this.links.forget();
    this.messages = messages;
    this.readouts = new Readouts({ sim, running: () => this.running, speed: () => this.speed, backend: () => this.backend, extra: () => this.live.hudLines() });
    this.links = new SceneLinks({ sim, messages, load, statusBox: () => this.panelPart?.el.status ?? null, share: Boolean(this.options.share) });
    this.edits = new SceneEdits({ sim, viewer, messages, changed, shown: (list) => this.showSelection(list) });
    this.pinning = new Pinning({ sim, viewer, canvas: this.canvas, messages, changed,
      selectionShown: (selection) => { if (this.panelPart) this.panelPart.el.selection.value = selection; },
      closeDrawer: () => this.frameDom.closeDrawer() });
    this.urdf = new UrdfLoading({ sim, messages, load, showUrdf: (xml, meshes) => {
      messages.guard(() => this.viewer.setUrdf(xml, { meshes }));
      this.drawWorld();
      this.fit();
    } });
    this.presetMeshes = new PresetMeshes({ base: this.options.presetMeshes, sim, viewer, messages });
    this.live = new LiveInput({ sim, messages, estimator: this.options.estimator, speed: () => this.speed, changed, selected: () => this.edits.selected });
  }

  // ---- DOM ----

  build() {
    const full = this.controls === 'full';
    const wanted = full ? ['clearance', 'dh', 'qdot'] : (this.options.plot ? [this.options.plot] : []);
    this.plotStrip = new PlotStrip(wanted);
    this.frameDom = new WidgetFrame({
      options: this.options,
      controls: this.controls,
      canvas: this.canvas,
      overlays: [this.readouts.statsBox, this.readouts.hud, this.live.thumb],
      messages: this.messages,
      plots: this.plotStrip.element,
      onDrop: (e) => this.urdf.drop(e),
      bar: { toggleRun: () => this.toggleRun(), reset: () => this.reset(), fit: () => this.fit() },
    });
    this.container = this.frameDom.container;
    // Notices go to the corner of the view that hides the least of the arm.
    const place = () => this.viewer && placeNotices(this.frameDom.notices, this.canvas, armPoints(this.messages.guard(() => this.viewer.state())?.screenNodes, window.devicePixelRatio || 1));
    this.events = new EventFeed({ notices: this.frameDom.notices, log: this.frameDom.log, onSeek: (t) => this.seek(t), onNotices: place });
    this.playButton = this.frameDom.playButton;
    this.loop = new FrameLoop({
      sim: this.sim, viewer: () => this.viewer, drawWorld: () => this.drawWorld(),
      readouts: this.readouts, plots: this.plotStrip, trace: this.trace, events: this.events,
      running: () => this.running, speed: () => this.speed, offscreen: () => this.offscreen, beforeSteps: () => this.live.apply(),
      onError: (message) => this.showError(message),
    });
    if (full) this.container.append(this.buildPanel());
    this.root.append(this.frameDom.style, this.container);
  }

  buildPanel() {
    const study = buildDependability({ sim: this.sim, messages: this.messages, selected: () => this.edits.selected });
    this.study = study.context.study;
    this.studyContext = study.context;
    this.panelPart = new Panel({
      sim: this.sim,
      sections: { pinned: this.pinning.section(), dependability: study.element, live: this.live.section() },
      parts: { edits: this.edits, links: this.links, urdf: this.urdf, messages: this.messages },
      actions: {
        toggleRun: () => this.toggleRun(),
        speed: () => this.speed,
        setSpeed: (speed) => { this.speed = speed; },
        setPreset: (name) => this.setPreset(name),
        setController: (partial) => this.setController(partial),
        rebuild: (changes, box) => this.rebuild(changes, box),
        withRobot: (robot, q0, box, label) => this.withRobot(robot, q0, box, label),
        fit: () => this.fit(),
        setView: (view) => this.messages.guard(() => this.viewer.setView(view)),
        applyDisplay: () => this.applyDisplay(),
        exportTrace: (format) => this.exportTrace(format),
        singleStep: () => this.singleStep(),
        reset: () => this.reset(),
        toggleHelp: () => this.toggleHelp(),
      },
    });
    this.playButton = this.panelPart.el.playButton;
    return this.panelPart.element;
  }

  /** The panel shows the selected obstacle again (and the list of obstacles when `list`). */
  showSelection(list) {
    if (!this.panelPart) return;
    if (list) this.panelPart.refreshObstacleList();
    this.panelPart.refreshSelected();
  }

  // ---- start ----

  /** Loads the wasm, starts the viewer on `scenario` (an object or an example name). */
  async start(scenario) {
    const wasm = await loadWasm();
    this.sim.wasm = wasm;
    useLibrary(wasm);
    if (typeof wasm.World !== 'function') {
      throw new Error('This build of the library has no simulation (World): the page needs the avoidance module.');
    }
    const backend = this.options.backend ?? 'auto';
    const antialias = this.options.antialias ?? (backend !== 'webgl2' && (await softwareWebGpu()) ? false : undefined);
    // The element owns its canvas: drawn through its OffscreenCanvas, which the
    // browser composites more cheaply (render/gpu.rs).
    this.viewer = await wasm.Viewer.create(this.canvas, { backend, view: this.options.view ?? 'auto', antialias, offscreen: true });
    this.backend = this.viewer.backend;
    this.followSize();
    this.wireInput();
    if (this.panelPart) {
      // The library names its presets; the page does not keep its own list.
      if (typeof wasm.presetNames === 'function') fillPresets(this.panelPart.el, wasm.presetNames());
      this.panelPart.offerExamples(wasm.exampleScenarioNames(), (name) => this.loadScenario(wasm.exampleScenario(name), `example ${name}`));
    }
    let initial = scenario;
    if (typeof scenario === 'string') {
      try {
        initial = wasm.exampleScenario(scenario);
      } catch (err) {
        throw new Error(`${errorText(err)} (examples: ${wasm.exampleScenarioNames().join(', ')})`);
      }
    }
    const failure = this.loadScenario(initial, typeof scenario === 'string' ? `example ${scenario}` : 'scenario');
    if (failure) throw new Error(failure);
    await this.loop.run();
  }

  /** The drawing buffer follows the canvas's size; an untouched view is framed again. */
  followSize() {
    const resize = () => {
      const dpr = window.devicePixelRatio || 1;
      this.messages.guard(() => this.viewer.resize(Math.max(1, Math.round(this.canvas.clientWidth * dpr)), Math.max(1, Math.round(this.canvas.clientHeight * dpr))));
    };
    resize();
    new ResizeObserver(() => {
      resize();
      // A view the person has not moved follows the widget's size.
      if (!this.cameraTouched) this.fit();
    }).observe(this.canvas);
  }

  wireInput() {
    wireInput({
      canvas: this.canvas,
      keys: this.options.keyboardTarget ?? this.container,
      viewer: () => this.viewer,
      pick: (origin, direction) => this.sim.world.pick(origin, direction),
      shapeOf: (id) => this.sim.shapeOf(id),
      edits: this.edits,
      pinning: this.pinning,
      messages: this.messages,
      engage: (on) => { this.engaged = on ?? (this.options.captureWheel ?? false); },
      engaged: () => this.engaged,
      cameraMoved: () => { this.cameraTouched = true; },
      refreshSelected: () => this.panelPart?.refreshSelected(),
      full: this.controls === 'full',
      commands: {
        toggleRun: () => this.toggleRun(),
        singleStep: () => this.singleStep(),
        reset: () => this.reset(),
        fit: () => this.fit(),
        toggleHelp: (show) => this.toggleHelp(show),
        showView: (view) => {
          this.viewer.setView(view);
          this.fit();
          if (this.panelPart) this.panelPart.el.viewSelect.value = view;
        },
      },
    });
  }

  destroy() {
    this.loop.stop();
    this.live.stop();
    this.sim.free();
    this.viewer?.free();
    this.viewer = null;
  }

  // ---- scenario ----

  /**
   * Replaces the scene with `scenario`. Returns `null`, or the error message
   * (shown in the widget) when the scenario is refused; the scene is then untouched.
   */
  loadScenario(scenario, label = 'scenario') {
    const sim = this.sim;
    let world;
    let spec;
    let robotSet = false;
    try {
      if (scenario === null || typeof scenario !== 'object' || Array.isArray(scenario)) throw new Error('expected a scenario object');
      world = new sim.wasm.World(scenario);
      spec = sim.robotSpecOf(scenario.robot);
      robotSet = true;
      this.viewer.setRobot(spec);
      // The direction and the points the scenario asks to be seen from
      // (checked with the world above); `fit` below applies the points.
      if (scenario.camera) this.viewer.setCamera(scenario.camera);
    } catch (err) {
      world?.free();
      if (sim.scenario && robotSet) {
        // Back to the current robot, its camera and its world in the view.
        this.messages.guard(() => {
          this.viewer.setRobot(sim.robotSpec);
          if (sim.scenario.camera) this.viewer.setCamera(sim.scenario.camera);
          this.drawWorld();
        });
      }
      const message = `The ${label} could not be loaded; the current scene is unchanged.\n${errorText(err)}`;
      this.showError(message);
      return message;
    }
    sim.replace(world, scenario, spec);
    this.edits.clear();
    this.afterRebuild();
    this.previousLabel = this.label;
    this.label = label;
    if (this.frameDom.title) this.frameDom.title.textContent = label;
    this.panelPart?.showExample(label);
    this.messages.status(`Loaded ${label}.`);
    this.messages.clearError();
    this.refreshPanel();
    this.fit();
    if (label !== 'shared scenario') this.links.forget();
    this.presetMeshes.show();
    return null;
  }

  /** Rebuilds the world from the current scenario with `changes` (fields replaced); keeps the old one on error. */
  rebuild(changes, messageBox) {
    const next = { ...this.sim.currentScenario({ keepQ0: true }), ...changes };
    let world;
    try {
      world = new this.sim.wasm.World(next);
    } catch (err) {
      const message = errorText(err);
      if (messageBox) messageBox.textContent = message;
      else this.showError(message);
      return false;
    }
    if (messageBox) messageBox.textContent = '';
    this.sim.replace(world, next);
    this.afterRebuild();
    this.links.forget();
    return true;
  }

  afterRebuild() {
    this.loop.clock.restart();
    this.drawWorld();
    this.events.clear();
    this.trace.clear();
    this.live.feed.reset();
    const speeds = robotRows(this.sim.robotSpec).map((r) => r.joint.maxVelocity).filter(Number.isFinite);
    this.plotStrip.clear(this.sim.influence(), speeds.length ? Math.min(...speeds) : NaN);
  }

  // ---- edits ----

  setController(partial) {
    const sim = this.sim;
    const ok = this.messages.guard(() => { sim.world.setController(partial); return true; }, this.panelPart?.el.controllerMessage);
    if (ok) {
      sim.recordController(partial);
      this.links.forget();
      this.pinning.refresh();
    } else {
      // Refused: the menus show what is in force.
      this.panelPart?.showController(sim.scenario.controller ?? {});
    }
    return Boolean(ok);
  }

  setPreset(name) {
    if (name === 'custom') return;
    const dof = robotRows(this.sim.wasm.robotPreset(name)).length;
    this.withRobot({ preset: name }, new Array(dof).fill(0), this.panelPart?.el.dhMessage, `robot preset ${name}`);
  }

  /**
   * Replaces the robot (and q0); keeps everything as it was on error, with a
   * message naming `what` (the preset or the edited robot the person chose).
   */
  withRobot(robot, q0, box, what = 'robot') {
    // Pinned points name rows of the old robot: a new robot starts without them.
    const current = this.sim.currentScenario({ keepQ0: true });
    const next = { ...current, robot, q0, controller: withoutPins(current.controller) };
    const message = this.loadScenario(next, what);
    if (!message) {
      // The scene keeps its name; only the robot changed.
      this.label = this.previousLabel ?? what;
      if (this.frameDom.title) this.frameDom.title.textContent = this.label;
    }
    if (message && box) {
      box.textContent = message;
      this.messages.clearError();
    }
    return !message;
  }

  // ---- simulation ----

  /**
   * Hands the world to the viewer: `drawWorld` reads it in Rust; a build
   * without it gets the state object read this frame (`drawState`).
   */
  drawWorld() {
    const sim = this.sim;
    if (typeof this.viewer.drawWorld === 'function') this.viewer.drawWorld(sim.world);
    else this.viewer.drawState(sim.state ?? sim.world.state());
  }

  toggleRun() {
    this.running = !this.running;
    if (this.playButton) this.playButton.textContent = this.running ? 'Pause' : 'Run';
  }

  singleStep() {
    if (this.running) this.toggleRun();
    this.loop.clock.pendingSteps += 1;
  }

  reset() {
    this.rebuild({});
    this.fit();
    this.messages.status('Reset.');
  }

  /** Moves the plots' cursor to time `t` (s) and pauses, so the moment can be read. */
  seek(t) {
    if (this.running) this.toggleRun();
    this.plotStrip.mark(t);
    this.loop.seekPending = true;
    this.messages.status(`Plots marked at t = ${t.toFixed(3)} s.`);
  }

  // ---- camera ----

  /** Frames the robot and the obstacles near it (about 60 % of the view). */
  fit() {
    if (!this.viewer) return;
    // A portrait view (a phone) is limited by its width: fill more of it.
    const portrait = this.canvas.clientHeight > 1.2 * this.canvas.clientWidth;
    this.messages.guard(() => this.viewer.fit?.(portrait ? 0.9 : 0.85, this.overlayTop()));
    this.cameraTouched = false;
    this.sim.edited = true;
  }

  /**
   * Drawing-buffer pixels at the top of the view covered by the stats and
   * the HUD (and a small margin): a fit frames the scene below them.
   */
  overlayTop() {
    const { hud, statsBox } = this.readouts;
    const top = this.canvas.getBoundingClientRect().top;
    const bottoms = [statsBox, hud].filter((e) => e && !e.hidden && e.offsetParent !== null)
      .map((e) => e.getBoundingClientRect().bottom - top + (e === hud ? this.readouts.growth() : 0));
    const covered = bottoms.length ? Math.max(0, ...bottoms) + 6 : 0;
    return covered * (window.devicePixelRatio || 1);
  }

  /** Off screen the simulation waits (an IntersectionObserver tells). */
  setOffscreen(offscreen) {
    this.offscreen = offscreen;
    this.loop.clock.lastNow = undefined;
  }

  /** Downloads the run so far: `format` is `"csv"` or `"json"`. */
  exportTrace(format) {
    const names = robotRows(this.sim.robotSpec).map((r) => r.label);
    this.trace.download(format, names, this.label ?? 'run');
  }

  // ---- panel ----

  showError(message) { this.messages.error(message); }

  applyDisplay() {
    const get = (id) => this.root.getElementById?.(id)?.checked ?? this.root.querySelector(`#${id}`)?.checked;
    this.messages.guard(() => this.viewer.setDisplay({ meshes: get('show-meshes') ?? true, volumes: get('show-volumes'), nodes: get('show-nodes'), axes: get('show-axes'), grid: true }));
  }

  /** The panel shows the scene as it is now (nothing without a panel). */
  refreshPanel() {
    if (!this.panelPart) return;
    this.panelPart.refresh();
    this.pinning.refresh();
    refreshDependability(this.studyContext);
  }

  toggleHelp(show) { this.frameDom.toggleHelp(show); }

  // ---- what pages, the console and the tests read ----

  get wasm() { return this.sim.wasm; } get world() { return this.sim.world; }
  get scenario() { return this.sim.scenario; } get robotSpec() { return this.sim.robotSpec; } get state() { return this.sim.state; }
  get edited() { return this.sim.edited; } set edited(on) { this.sim.edited = on; }
  get selected() { return this.edits.selected; }
  get stats() { return this.readouts.stats; } get hud() { return this.readouts.hud; }
  get plots() { return this.plotStrip.plots; }
  get panel() { return this.panelPart?.el; }
  get errorBox() { return this.messages.errorBox; } get errorMessage() { return this.messages.errorMessage; }
  get urdfReport() { return this.urdf.report; }
  get presetFiles() { return this.presetMeshes.files; } set presetFiles(files) { this.presetMeshes.files = files; }
  get presetMeshesShown() { return this.presetMeshes.shown; }
  get lastHash() { return this.links.lastHash; } set lastHash(hash) { this.links.lastHash = hash; }
  select(id) { this.edits.select(id); }
  currentScenario(options) { return this.sim.currentScenario(options); }
  share() { return this.links.share(); }
  shareUrl() { return this.links.shareUrl(); }
  loadHash(hash) { return this.links.loadHash(hash); }

  /** A snapshot: the world's state, the viewer's, the frame counter and stats. */
  snapshot() {
    if (!this.viewer) return { backend: null, frames: this.loop.frames };
    const world = this.sim.world.state();
    return { ...this.viewer.state(), q: Array.from(world.q), world, frames: this.loop.frames, stats: { ...this.stats }, selected: this.selected, running: this.running, speed: this.speed,
      events: this.events.snapshot(), offscreen: Boolean(this.offscreen), engaged: Boolean(this.engaged) };
  }
}
