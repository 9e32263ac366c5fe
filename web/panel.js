// The side panel of the full playground: scenario, simulation, obstacles,
// controller, pinned control points (built in `pinning.js`), sensing, the robot's DH table with its joint limits (every
// chain, branches included), initial joints and the view.
//
// Every value typed is checked in place (decimal numbers only, within sane
// bounds) and refused with the reason; the robot is applied only when the
// library accepts it.
//
// Owns: the panel's elements (`el`: menus, fields, tables, message lines,
// the status line) and what they show. Interface: `sim` (read: the scenario,
// the robot, the world's controller, the state) and `actions`, the named
// commands its controls call (listed in `PanelActions` below) and the
// parts it drives (edits, links, URDF loading, messages); the pinned
// points' and the dependability sections are built by their own parts and
// handed in as `sections`.
import { clone, h } from './dom.js';
import { HUMAN_MOTIONS, PALETTE, rotateShape, scaleShape, shapeCenter, translateShape } from './shapes.js';
import { downloadScenario } from './scenario-io.js';

/**
 * The presets offered before the library is loaded; `fillPresets` replaces
 * them with the library's own list (`presetNames()`).
 */
export const PRESETS = ['planar3', 'lwr4', 'iiwa14', 'panda', 'ur5', 'dual-arm'];

/** Offers the library's presets (`names`), then the DH table. */
export function fillPresets(p, names) {
  const current = p.preset.value;
  p.preset.replaceChildren(...names.map((n) => h('option', { value: n }, n)), h('option', { value: 'custom' }, 'custom (DH table)'));
  p.preset.value = names.includes(current) || current === 'custom' ? current : 'custom';
}

/** A decimal number as a person types it: no hex, no `Infinity`, no blanks inside. */
const DECIMAL = /^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d{1,3})?$/;
const TWO_PI = 2 * Math.PI;

/** The DH columns and the limit columns: key, header, unit, bounds, whether it may be empty. */
const DH_COLUMNS = [
  { k: 'a', head: 'a', unit: 'm', lo: -10, hi: 10 },
  { k: 'alpha', head: 'α', unit: 'rad', lo: -TWO_PI, hi: TWO_PI },
  { k: 'd', head: 'd', unit: 'm', lo: -10, hi: 10 },
  { k: 'theta', head: 'θ', unit: 'rad', lo: -TWO_PI, hi: TWO_PI },
];
const LIMIT_COLUMNS = [
  { k: 'min', head: 'min', unit: 'rad|m', lo: -100, hi: 100, optional: true },
  { k: 'max', head: 'max', unit: 'rad|m', lo: -100, hi: 100, optional: true },
  { k: 'maxVelocity', head: 'v max', unit: '/s', lo: 1e-6, hi: 1e3, optional: true },
  { k: 'maxAcceleration', head: 'a max', unit: '/s²', lo: 1e-6, hi: 1e5, optional: true },
  { k: 'maxJerk', head: 'j max', unit: '/s³', lo: 1e-6, hi: 1e7, optional: true },
  { k: 'maxTorque', head: 'τ max', unit: 'N·m|N', lo: 1e-6, hi: 1e5, optional: true },
];

/**
 * Checks one typed value; returns `{ value }` or `{ error }`. Empty is
 * `undefined` for optional columns, an error otherwise.
 */
export function parseCell(text, column) {
  const t = String(text).trim();
  if (t === '') return column.optional ? { value: undefined } : { error: 'is empty' };
  if (!DECIMAL.test(t)) return { error: `"${t}" is not a decimal number` };
  const value = Number(t);
  if (!Number.isFinite(value)) return { error: `"${t}" is not a finite number` };
  if (value < column.lo || value > column.hi) return { error: `${t} is outside [${fmt(column.lo)}, ${fmt(column.hi)}] ${column.unit}` };
  return { value };
}

const fmt = (x) => (Math.abs(x) === TWO_PI ? `${x < 0 ? '−' : ''}2π` : String(x));
const shown = (x) => (x === undefined || x === null ? '' : String(Number(Number(x).toPrecision(6))));

/** Every DH row of a spec with its chain: the main chain, then each branch. */
export function robotRows(spec) {
  const rows = (spec.joints ?? []).map((j, i) => ({ chain: 'main', index: i, label: `${i + 1}`, joint: j }));
  (spec.branches ?? []).forEach((b, bi) => b.joints.forEach((j, i) => rows.push({ chain: bi, index: i, label: `${b.name ?? `branch ${bi + 1}`} ${i + 1}`, joint: j })));
  return rows;
}

const field = (label, input) => h('div', { class: 'row' }, h('label', {}, label, input));

/** The panel's commands that are the parts' own. */
function panelCommands(sim, { edits, links, urdf, messages }) {
  return {
    loadFile: (file) => links.loadFile(file),
    loadUrdfItems: (items) => urdf.loadItems(items),
    currentScenario: () => sim.currentScenario(),
    share: () => links.share(),
    addObstacle: (type) => edits.addObstacle(type),
    selected: () => edits.selected,
    select: (id) => edits.select(id),
    removeSelected: () => edits.removeSelected(),
    editSelected: (f) => edits.editSelected(f),
    openTrack: (file) => edits.openTrack(file),
    status: (text) => messages.status(text),
  };
}

/**
 * @typedef {object} PanelActions
 * @property {() => void} toggleRun
 * @property {() => number} speed
 * @property {(speed: number) => void} setSpeed
 * @property {(name: string) => void} setPreset
 * @property {(partial: object) => boolean} setController
 * @property {(changes: object, box: HTMLElement) => boolean} rebuild
 * @property {(robot: object, q0: number[], box: HTMLElement, label: string) => boolean} withRobot
 * @property {() => void} fit
 * @property {(view: string) => void} setView
 * @property {() => void} applyDisplay
 * @property {(format: string) => void} exportTrace
 * @property {() => void} singleStep
 * @property {() => void} reset
 * @property {() => void} toggleHelp
 */

export class Panel {
  /**
   * @param {{ sim: import('./sim.js').Sim, actions: PanelActions, sections: { pinned: HTMLElement[], dependability: HTMLElement },
   *           parts: { edits: import('./scene-edits.js').SceneEdits, links: import('./share.js').SceneLinks,
   *                    urdf: import('./urdf-files.js').UrdfLoading, messages: import('./messages.js').Messages } }} host
   */
  constructor(host) {
    this.sim = host.sim;
    this.parts = host.parts;
    this.actions = { ...host.actions, ...panelCommands(host.sim, host.parts) };
    this.el = {};
    this.element = this.build(host.sections);
  }

  build(sections) {
    const pg = this.actions;
    const p = this.el;
    p.example = h('select', { id: 'example', 'aria-label': 'example scenario' });
    p.file = h('input', { type: 'file', accept: '.json,application/json', hidden: true, id: 'file', onchange: async () => { await pg.loadFile(p.file.files[0]); p.file.value = ''; } });
    const picked = (input) => () => {
      const items = [...input.files].map((file) => ({ path: file.webkitRelativePath || file.name, file }));
      input.value = '';
      pg.loadUrdfItems(items);
    };
    p.urdfFolder = h('input', { type: 'file', hidden: true, id: 'urdf-folder', webkitdirectory: true, multiple: true });
    p.urdfFolder.onchange = picked(p.urdfFolder);
    p.urdfFiles = h('input', { type: 'file', hidden: true, id: 'urdf-files', multiple: true, accept: '.urdf,.zip,.stl,.obj,.dae,.gltf,.glb,.bin' });
    p.urdfFiles.onchange = picked(p.urdfFiles);
    p.status = h('div', { class: 'hint', id: 'status', 'aria-live': 'polite' });
    p.playButton = h('button', { type: 'button', id: 'run', onclick: () => pg.toggleRun() }, 'Pause');
    p.speed = h('input', { type: 'range', id: 'speed', min: '-3', max: '1', step: '0.01', value: String(Math.log2(pg.speed()) / 2), 'aria-label': 'simulation speed',
      oninput: () => { pg.setSpeed(4 ** Number(p.speed.value)); p.speedOut.textContent = `${pg.speed().toFixed(2)}×`; } });
    p.speedOut = h('output', {}, `${pg.speed().toFixed(2)}×`);

    p.preset = h('select', { id: 'preset', onchange: () => pg.setPreset(p.preset.value) },
      PRESETS.map((n) => h('option', { value: n }, n)), h('option', { value: 'custom' }, 'custom (DH table)'));
    p.convention = h('select', { id: 'convention' }, h('option', { value: 'standard' }, 'standard DH'), h('option', { value: 'modified' }, 'modified DH'));
    p.dh = h('tbody');
    p.limits = h('tbody');
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
    for (const key of ['mode', 'selection']) p[key].addEventListener('change', () => pg.setController({ [key]: p[key].value }));
    for (const key of ['influenceDistance', 'repulsionGain', 'maxRepulsionSpeed', 'transitionTime']) {
      p[key].addEventListener('change', () => { if (p[key].value !== '') pg.setController({ [key]: Number(p[key].value) }); });
    }
    p.bound = num('noise-bound', '0.005', 'm');
    p.sigma = num('noise-sigma', '0.005', 'm');
    p.switchWindow = num('switch-window', '0.1', 's');
    p.maxSwitches = num('max-switches', '1', '');
    p.onChattering = h('select', { id: 'on-chattering' }, ['stop', 'lock'].map((m) => h('option', { value: m }, m)));
    p.lockTime = num('lock-time', '0.1', 's');
    p.worldMessage = h('div', { class: 'message', id: 'world-message' });
    p.obstacles = h('ul', { class: 'obstacles', id: 'obstacle-list', 'aria-label': 'obstacles' });
    p.selectedBox = h('div', { id: 'selected' });
    p.viewSelect = h('select', { id: 'view-select', onchange: () => { pg.setView(p.viewSelect.value); pg.fit(); } },
      [['auto', 'auto'], ['3d', '3D'], ['top', 'top'], ['front', 'front'], ['side', 'side']].map(([v, t]) => h('option', { value: v }, t)));
    const check = (id, label, on) => h('label', { class: 'row' }, h('input', { type: 'checkbox', id, checked: on, onchange: () => pg.applyDisplay() }), label);
    const button = (id, label, onclick, title) => h('button', { type: 'button', id, onclick, title }, label);

    return h('aside', { class: 'panel', id: 'panel', 'aria-label': 'controls' },
      h('h3', {}, 'Scenario'),
      h('div', { class: 'row' }, p.example, button('open', 'Open…', () => p.file.click()),
        button('save', 'Save', () => downloadScenario(pg.currentScenario(), 'scenario.json'), 'download the scene as JSON'),
        button('share', 'Share', () => pg.share(), 'copy a link that restores the scene'), p.file),
      h('div', { class: 'row' }, 'trace', button('export-csv', 'CSV', () => pg.exportTrace('csv'), 'download the run so far as CSV'),
        button('export-json', 'JSON', () => pg.exportTrace('json'), 'download the run so far as JSON')),
      p.status,
      h('h3', {}, 'Simulation'),
      h('div', { class: 'row' }, p.playButton, button('step', 'Step', () => pg.singleStep()), button('reset', 'Reset', () => pg.reset(), 'restart and frame the view'),
        button('fit', 'Fit', () => pg.fit(), 'frame the robot and the obstacles (F, double click)'), button('help-button', '?', () => pg.toggleHelp(), 'keys')),
      h('div', { class: 'row' }, h('label', {}, 'speed', p.speed, p.speedOut)),
      h('h3', {}, 'Obstacles'),
      h('div', { class: 'palette' }, PALETTE.map((t, k) => button(`add-${t}`, t, () => pg.addObstacle(t), `add a ${t} (key ${(k + 1) % 10})`))),
      p.obstacles, p.selectedBox,
      ...(sections.live ?? []),
      h('h3', {}, 'Controller'),
      field('mode', p.mode), field('selection', p.selection),
      field('influence distance (m)', p.influenceDistance), field('repulsion gain', p.repulsionGain),
      field('max repulsion speed (m/s)', p.maxRepulsionSpeed), field('transition time (s/value)', p.transitionTime),
      p.controllerMessage,
      ...sections.pinned,
      h('h3', {}, 'Sensing and dependability'),
      field('noise bound (m)', p.bound), field('noise σ (m)', p.sigma),
      field('switch window (s)', p.switchWindow), field('max switches', p.maxSwitches),
      field('on chattering', p.onChattering), field('lock time (s)', p.lockTime),
      h('div', { class: 'row' }, button('apply-sensing', 'Apply (restarts)', () => this.applySensing())),
      p.worldMessage,
      sections.dependability,
      h('h3', {}, 'Robot'),
      field('preset', p.preset), field('convention', p.convention),
      h('div', { class: 'row', title: 'a URDF with its meshes (STL, OBJ, COLLADA, glTF): a folder, a zip or the files; or drop them on the view' },
        'URDF', button('open-urdf-folder', 'Folder…', () => p.urdfFolder.click()), button('open-urdf-files', 'Files or zip…', () => p.urdfFiles.click()),
        p.urdfFolder, p.urdfFiles),
      h('table', { class: 'dh', id: 'dh-table' }, h('caption', {}, 'DH table (m, rad)'),
        h('thead', {}, h('tr', {}, ['#', ...DH_COLUMNS.map((c) => c.head), 'type'].map((c) => h('th', {}, c)))), p.dh),
      h('table', { class: 'dh', id: 'limits-table' }, h('caption', {}, 'joint limits (rad or m, per s, s², s³; N·m or N; empty: default)'),
        h('thead', {}, h('tr', {}, ['#', ...LIMIT_COLUMNS.map((c) => c.head)].map((c) => h('th', {}, c)))), p.limits),
      h('div', { class: 'row' }, button('apply-dh', 'Apply robot', () => this.applyDh())),
      p.dhMessage,
      h('h3', {}, 'Initial joints'),
      p.joints,
      h('h3', {}, 'View'),
      field('camera', p.viewSelect),
      check('show-meshes', 'meshes', true), check('show-volumes', 'volumes', true), check('show-nodes', 'nodes', true), check('show-axes', 'frame axes', false));
  }

  /** Restarts the simulation with the sensing and dependability typed in the panel. */
  applySensing() {
    const p = this.el;
    const n = (input) => (input.value === '' ? undefined : Number(input.value));
    const noise = { bound: n(p.bound), sigma: n(p.sigma) };
    const scenario = this.sim.scenario;
    const sensing = { ...(scenario.sensing ?? {}) };
    if (noise.bound !== undefined || noise.sigma !== undefined) sensing.default = { ...(sensing.default ?? {}), ...clone(noise) };
    const dependability = { ...(scenario.dependability ?? {}), onChattering: p.onChattering.value };
    for (const key of ['switchWindow', 'maxSwitches', 'lockTime']) if (n(p[key]) !== undefined) dependability[key] = n(p[key]);
    if (this.actions.rebuild({ sensing, dependability }, p.worldMessage)) this.actions.status('Sensing and dependability applied; the simulation restarted.');
  }

  /** Offers the library's example scenes; `onPick(name)` loads one. */
  offerExamples(names, onPick) {
    const select = this.el.example;
    for (const name of names) select.append(h('option', { value: name }, name));
    select.prepend(h('option', { value: '', disabled: true }, 'examples…'));
    select.addEventListener('change', () => { if (select.value) onPick(select.value); });
  }

  /** Marks the example `label` names (`example <name>`) in the menu, or none. */
  showExample(label) {
    const select = this.el.example;
    const name = label.startsWith('example ') ? label.slice('example '.length) : '';
    select.value = [...select.options].some((o) => o.value === name) ? name : '';
  }

  /** The controller's menus show `c` (after a refused change: what is in force). */
  showController(c) {
    this.el.mode.value = c.mode ?? 'velocity';
    this.el.selection.value = c.selection ?? 'perObstacle';
  }

  fillRobotTables() {
    const p = this.el;
    const rows = robotRows(this.sim.robotSpec);
    p.dh.replaceChildren(...rows.map((r, i) => h('tr', {},
      h('th', { scope: 'row' }, r.label),
      DH_COLUMNS.map((c) => cellInput(i, c, r.joint[c.k] ?? 0, `joint ${r.label}`)),
      h('td', {}, h('select', { 'data-k': 'type', 'aria-label': `joint ${r.label} type` },
        ['revolute', 'prismatic'].map((t) => h('option', { value: t, selected: (r.joint.type ?? 'revolute') === t }, t)))))));
    p.limits.replaceChildren(...rows.map((r, i) => h('tr', {},
      h('th', { scope: 'row' }, r.label),
      LIMIT_COLUMNS.map((c) => cellInput(i, c, r.joint[c.k], `joint ${r.label}`)))));
    for (const input of [...p.dh.querySelectorAll('input'), ...p.limits.querySelectorAll('input')]) input.addEventListener('input', () => this.readRobotTables());
    p.dhMessage.textContent = '';
  }

  /** Reads both tables; marks each bad cell and lists the reasons. Returns the joints or null. */
  readRobotTables() {
    const p = this.el;
    const rows = robotRows(this.sim.robotSpec);
    const problems = [];
    const joints = rows.map((r, i) => {
      const joint = { ...r.joint };
      for (const [tbody, columns] of [[p.dh, DH_COLUMNS], [p.limits, LIMIT_COLUMNS]]) {
        const tr = tbody.children[i];
        for (const c of columns) {
          const input = tr.querySelector(`[data-k="${c.k}"]`);
          const { value, error } = parseCell(input.value, c);
          input.setAttribute('aria-invalid', error ? 'true' : 'false');
          input.title = error ? `${c.head}: ${error}` : `${c.head} (${c.unit})`;
          if (error) problems.push(`joint ${r.label}: ${c.head} ${error}`);
          else if (value === undefined) delete joint[c.k];
          else joint[c.k] = value;
        }
      }
      joint.type = p.dh.children[i].querySelector('[data-k="type"]').value;
      if (joint.min !== undefined && joint.max !== undefined && !(joint.min < joint.max)) problems.push(`joint ${r.label}: min must be below max`);
      return joint;
    });
    p.dhMessage.textContent = problems.join('\n');
    return problems.length ? null : joints;
  }

  /** Applies the edited tables as a custom robot (chains kept); false when refused. */
  applyDh() {
    const pg = this.actions;
    const p = this.el;
    const joints = this.readRobotTables();
    if (!joints) return false;
    const spec = structuredClone(this.sim.robotSpec);
    spec.convention = p.convention.value;
    const rows = robotRows(this.sim.robotSpec);
    rows.forEach((r, i) => {
      if (r.chain === 'main') spec.joints[r.index] = joints[i];
      else spec.branches[r.chain].joints[r.index] = joints[i];
    });
    const q0 = rows.map((_, i) => this.sim.scenario.q0?.[i] ?? 0);
    if (!pg.withRobot(spec, q0, p.dhMessage, 'edited robot')) return false;
    p.dhMessage.textContent = '';
    p.preset.value = 'custom';
    pg.status('Robot applied.');
    return true;
  }

  /** Shows the scene as it is now: robot tables, controller, sensing, joints, obstacles. */
  refresh() {
    const p = this.el;
    const s = this.sim.scenario;
    p.preset.value = typeof s.robot === 'object' && 'preset' in s.robot ? s.robot.preset : 'custom';
    p.convention.value = this.sim.robotSpec.convention ?? 'standard';
    this.fillRobotTables();
    // The configuration in effect: the library's defaults where the scenario is silent.
    const c = this.sim.world?.controller() ?? s.controller ?? {};
    p.mode.value = c.mode ?? 'velocity';
    p.selection.value = c.selection ?? 'perObstacle';
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

  buildJointSliders() {
    const pg = this.actions;
    const p = this.el;
    const q0 = this.sim.scenario.q0 ?? [];
    const rows = robotRows(this.sim.robotSpec);
    p.joints.replaceChildren(...rows.map((r, i) => {
      const j = r.joint;
      const lo = Number.isFinite(j.min) ? j.min : -Math.PI;
      const hi = Number.isFinite(j.max) ? j.max : Math.PI;
      const value = q0[i] ?? 0;
      const out = h('output', {}, value.toFixed(2));
      const slider = h('input', { type: 'range', id: `joint-${i}`, min: String(lo), max: String(hi), step: '0.01', value: String(value), 'aria-label': `initial joint ${r.label}` });
      slider.addEventListener('input', () => {
        const q = rows.map((_, k) => this.sim.scenario.q0?.[k] ?? 0);
        q[i] = Number(slider.value);
        out.textContent = q[i].toFixed(2);
        pg.rebuild({ q0: q }, p.worldMessage);
      });
      // Released: frame the new pose.
      slider.addEventListener('change', () => pg.fit());
      return h('div', { class: 'row' }, h('label', {}, `q${r.label}`, slider, out));
    }));
  }

  refreshObstacleList() {
    const pg = this.actions;
    const p = this.el;
    p.obstacles.replaceChildren(...(this.sim.scenario.obstacles ?? []).map((o) => h('li', {
      class: o.id === pg.selected() ? 'selected' : '',
      tabindex: '0',
      role: 'option',
      'aria-selected': String(o.id === pg.selected()),
      onclick: () => pg.select(o.id),
      onkeydown: (e) => { if (e.key === 'Enter' || e.key === ' ') { e.preventDefault(); pg.select(o.id); } },
    }, `${o.id} · ${o.shape?.type ?? '?'}${o.motion && o.motion.type !== 'static' ? ` · ${o.motion.type}` : ''}`)));
  }

  refreshSelected() {
    const pg = this.actions;
    const p = this.el;
    if (!pg.selected()) {
      p.selectedBox.replaceChildren(h('p', { class: 'hint' }, 'Click an obstacle to select it; drag to move it (Alt: along the view direction).'));
      return;
    }
    const shape = this.sim.shapeOf(pg.selected());
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
        pg.editSelected((s) => translateShape(s, delta));
      } }));
    const btn = (label, title, f) => h('button', { type: 'button', title, 'aria-label': title, onclick: () => pg.editSelected(f) }, label);
    const z = [0, 0, 1];
    const x = [1, 0, 0];
    p.selectedBox.replaceChildren(
      h('div', { class: 'row' }, h('strong', {}, pg.selected()), h('button', { type: 'button', id: 'delete', onclick: () => pg.removeSelected() }, 'Delete')),
      h('div', { class: 'row' }, 'centre', ...coords),
      h('div', { class: 'row' }, 'size', btn('−', 'shrink', (s) => scaleShape(s, 0.8)), btn('+', 'grow', (s) => scaleShape(s, 1.25)),
        'rotate z', btn('⟲', 'rotate +15° about z', (s) => rotateShape(s, z, Math.PI / 12)), btn('⟳', 'rotate −15° about z', (s) => rotateShape(s, z, -Math.PI / 12)),
        'x', btn('⟲', 'rotate +15° about x', (s) => rotateShape(s, x, Math.PI / 12))),
      ...(shape.type === 'human' ? this.humanRows() : []),
      h('pre', { class: 'hint', id: 'shape-json', style: 'white-space: pre-wrap; overflow-wrap: anywhere; margin: 0.2rem 0;' }, JSON.stringify(shape, (k, v) => (typeof v === 'number' ? Number(v.toFixed(4)) : v))),
    );
  }

  /** The selected human's motion (the library's clips) and a keypoint track to replay. */
  humanRows() {
    const pg = this.actions;
    const shape = this.sim.shapeOf(pg.selected());
    const current = shape?.animation?.clip ?? (shape?.animation?.keyframes ? 'keyframes' : 'none');
    const options = ['none', ...HUMAN_MOTIONS, ...(current === 'keyframes' ? ['keyframes'] : [])];
    const motion = h('select', { id: 'human-motion', 'aria-label': 'human motion',
      onchange: (e) => pg.editSelected((s) => this.withMotion(s, e.target.value)) },
    options.map((m) => h('option', { value: m, selected: m === current }, m)));
    const track = h('input', { type: 'file', id: 'human-track', accept: '.json,.csv,.bvh,application/json,text/csv', 'aria-label': 'open a keypoint track',
      onchange: (e) => pg.openTrack(e.target.files?.[0]) });
    return [
      h('div', { class: 'row' }, 'motion', motion),
      h('div', { class: 'row' }, h('label', { for: 'human-track' }, 'keypoint track (COCO-17, BODY-25, Kinect 32 in JSON or CSV; BVH)'), track),
      h('p', { class: 'hint' }, 'Drag a hand to move only its arm; drag the body to move the person.'),
    ];
  }

  /** `shape` with motion `name` of the library (a reach goes for the arm's tool). */
  withMotion(shape, name) {
    const out = { ...shape };
    delete out.animation;
    if (name === 'none' || name === 'keyframes') return name === 'keyframes' ? shape : out;
    const nodes = this.sim.state?.skeleton?.nodes ?? [];
    const tool = nodes[nodes.length - 1] ?? [0.4, 0, 0.5];
    out.animation = { clip: name, start: this.sim.state?.t ?? 0, ...(name === 'reach' ? { target: tool, speed: 1.5 } : {}) };
    return out;
  }
}

function cellInput(row, c, value, label) {
  return h('td', {}, h('input', { 'data-k': c.k, id: `${c.optional ? 'lim' : 'dh'}-${row}-${c.k}`, value: shown(value), inputmode: 'decimal',
    placeholder: c.optional ? 'default' : undefined, 'aria-label': `${label} ${c.head}`, title: `${c.head} (${c.unit})` }));
}
