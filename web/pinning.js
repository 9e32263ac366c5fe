// Pinned control points: points of the arm the person chooses, kept in
// `controller.pinned` as DH values `(link, d', a')` of the shorter
// manipulator, and used by the `pinned` selection.
//
// A point is pinned by clicking a link of the arm in Pin mode (the "Pin by
// clicking" button or the P key; the library's `World.pickSkeleton` finds the
// skeleton's point under the pointer) or by typing its DH values in the
// panel. Pinning switches the selection to `pinned`; removing the last point
// switches back to the selection used before. The points travel with the
// scene (Save, Share, Open). A refused point leaves everything as it was.
//
// Owns: Pin mode, the selection used before pinning, and the panel's
// "Pinned control points" section (`section()`, built only with a panel).
// Interface: `sim` (the world and the scenario), `viewer()` (picking rays),
// `canvas` (its Pin-mode cursor), `messages`, `changed()` (the scene no
// longer matches a shared link), `selectionShown(selection)` (the panel's
// selection menu) and `closeDrawer()` (a narrow widget's drawer would
// cover the arm).
import { clone, h } from './dom.js';
import { parseCell, robotRows } from './panel.js';

/** DH values typed into the panel: decimal metres within ±10 m. */
const LENGTH = { head: 'value', unit: 'm', lo: -10, hi: 10 };

const mm = (x) => (Math.abs(x) < 5e-7 ? '0.000' : x.toFixed(3));

/** The label of the DH row `link` (1-based; branches after the main chain) of `spec`. */
function rowLabel(spec, link) {
  return robotRows(spec ?? { joints: [] })[link - 1]?.label ?? String(link);
}

/** A controller without pinned points (for a new robot, whose rows differ). */
export function withoutPins(controller) {
  if (!controller?.pinned?.length && controller?.selection !== 'pinned') return controller;
  return { ...controller, pinned: [], selection: controller.selection === 'pinned' ? 'perObstacle' : controller.selection };
}

export class Pinning {
  /**
   * @param {{ sim: import('./sim.js').Sim, viewer: () => any, canvas: HTMLCanvasElement,
   *           messages: import('./messages.js').Messages, changed: () => void,
   *           selectionShown: (selection: string) => void, closeDrawer: () => void }} host
   */
  constructor(host) {
    this.host = host;
    this.mode = false;
    this.selectionBefore = undefined;
    this.el = null;
  }

  /** The pinned points of the scene (DH values). */
  points() {
    return this.host.sim.scenario?.controller?.pinned ?? [];
  }

  /** Turns Pin mode on or off (`on` omitted: toggles). */
  setMode(on) {
    const { messages } = this.host;
    this.mode = on === undefined ? !this.mode : Boolean(on);
    this.el?.mode.setAttribute('aria-pressed', String(this.mode));
    this.host.canvas.classList.toggle('pinning', this.mode);
    if (this.mode) this.host.closeDrawer();
    if (this.mode) messages.hint('Pin mode: click a link of the arm to pin a control point (P or Escape to stop)');
    messages.status(this.mode ? 'Pin mode: click a link of the arm to pin a control point there.' : 'Pin mode off.');
  }

  /**
   * Pins the skeleton's point under canvas pixel `px` (drawing-buffer
   * pixels). Returns the library's pick, or null when no link is under it
   * or the point was refused.
   */
  pinAt(px) {
    const { sim, messages } = this.host;
    const ray = this.host.viewer().rayAt(px[0], px[1]);
    const hit = messages.guard(() => sim.world.pickSkeleton(ray.origin, ray.direction));
    if (!hit) {
      messages.hint('No link of the arm under the pointer');
      return null;
    }
    return this.pin({ link: hit.link, d: hit.d, a: hit.a }) ? hit : null;
  }

  /** Adds a pinned point and selects `pinned`; false (message shown) when refused. */
  pin(point) {
    const sim = this.host.sim;
    const pinned = [...this.points(), point];
    const current = sim.scenario.controller?.selection;
    if (current && current !== 'pinned') this.selectionBefore = current;
    if (!this.apply(pinned, 'pinned')) return false;
    this.host.messages.status(`Pinned a control point on link ${rowLabel(sim.robotSpec, point.link)} (d′ ${mm(point.d)} m, a′ ${mm(point.a)} m); selection: pinned.`);
    return true;
  }

  /** Removes pinned point `k`; the last one gone, the selection goes back to the one before. */
  unpin(k) {
    const points = this.points();
    if (k < 0 || k >= points.length) return false;
    const pinned = points.filter((_, i) => i !== k);
    const current = this.host.sim.scenario.controller?.selection;
    const selection = pinned.length || current !== 'pinned' ? current : (this.selectionBefore ?? 'perObstacle');
    if (!this.apply(pinned, selection)) return false;
    this.host.messages.status(pinned.length ? `Removed pinned point ${k + 1}.` : `Removed the last pinned point; selection: ${selection}.`);
    // Keep the keyboard in the list.
    const items = this.el?.list.querySelectorAll('li');
    (items?.[Math.min(k, pinned.length - 1)] ?? this.el?.mode)?.focus();
    return true;
  }

  /** Gives the world `pinned` and `selection`; on refusal nothing changes and the reason is shown. */
  apply(pinned, selection) {
    const { sim, messages } = this.host;
    const partial = { pinned: clone(pinned), selection };
    const ok = messages.guard(() => { sim.world.setController(partial); return true; }, this.el?.message);
    if (!ok) return false;
    sim.recordController(partial);
    this.host.changed();
    sim.edited = true;
    this.host.selectionShown(selection);
    this.refresh();
    return true;
  }

  /** Pins the DH values typed in the panel (checked first; refused in place). */
  pinTyped() {
    const p = this.el;
    const link = Number(p.link.value);
    const values = {};
    const problems = [];
    for (const [k, input] of [['d', p.d], ['a', p.a]]) {
      const { value, error } = parseCell(input.value, LENGTH);
      input.setAttribute('aria-invalid', error ? 'true' : 'false');
      if (error) problems.push(`${k}′ ${error}`);
      else values[k] = value;
    }
    if (problems.length) {
      p.message.textContent = problems.join('\n');
      return false;
    }
    return this.pin({ link, d: values.d, a: values.a });
  }

  /** Rebuilds the list of pinned points and the link menu of the typed entry. */
  refresh() {
    const p = this.el;
    if (!p) return;
    const spec = this.host.sim.robotSpec;
    const points = this.points();
    const active = (this.host.sim.scenario.controller?.selection ?? 'perObstacle') === 'pinned';
    p.list.replaceChildren(...points.map((pt, k) => {
      const text = `${k + 1}. link ${rowLabel(spec, pt.link)} · d′ ${mm(pt.d)} · a′ ${mm(pt.a)} m`;
      const remove = h('button', { type: 'button', class: 'remove', 'aria-label': `remove pinned point ${k + 1}`, title: 'remove (Delete)',
        onclick: () => this.unpin(k) }, 'Remove');
      return h('li', { tabindex: '0', 'aria-label': `pinned point ${k + 1}: link ${rowLabel(spec, pt.link)}, d′ ${mm(pt.d)} m, a′ ${mm(pt.a)} m`,
        onkeydown: (e) => {
          if (e.target !== e.currentTarget || (e.key !== 'Delete' && e.key !== 'Backspace')) return;
          e.preventDefault();
          e.stopPropagation();
          this.unpin(k);
        } }, h('span', {}, text), remove);
    }));
    p.empty.hidden = points.length > 0;
    p.inactive.hidden = points.length === 0 || active;
    const rows = robotRows(spec ?? { joints: [] });
    const chosen = p.link.value;
    p.link.replaceChildren(...rows.map((r, i) => h('option', { value: String(i + 1) }, `link ${r.label}`)));
    if (chosen && Number(chosen) <= rows.length) p.link.value = chosen;
  }

  /** The panel's "Pinned control points" section (its elements, owned here). */
  section() {
    const value = (id, label) => h('input', { id, value: '0', inputmode: 'decimal', 'aria-label': label, title: `${label} (m)`, style: 'width: 4.2rem' });
    const p = {
      mode: h('button', { type: 'button', id: 'pin-mode', 'aria-pressed': 'false', title: 'then click a link of the arm (key P)',
        onclick: () => this.setMode() }, 'Pin by clicking (P)'),
      list: h('ul', { class: 'pinned-points', id: 'pinned-list', 'aria-label': 'pinned control points' }),
      empty: h('p', { class: 'hint', id: 'pinned-empty' }, 'None yet. Press "Pin by clicking" (or P) and click a link of the arm, or type DH values below.'),
      inactive: h('p', { class: 'hint', id: 'pinned-inactive', hidden: true }, 'Used when the selection is pinned.'),
      link: h('select', { id: 'pin-link', 'aria-label': 'pinned point link' }),
      d: value('pin-d', 'd′'),
      a: value('pin-a', 'a′'),
      message: h('div', { class: 'message', id: 'pin-message', role: 'status' }),
    };
    this.el = p;
    return [
      h('h3', {}, 'Pinned control points'),
      h('div', { class: 'row' }, p.mode),
      p.list, p.empty, p.inactive,
      h('div', { class: 'row' }, p.link, 'd′', p.d, 'a′', p.a,
        h('button', { type: 'button', id: 'pin-add', onclick: () => this.pinTyped() }, 'Pin')),
      p.message,
    ];
  }
}
