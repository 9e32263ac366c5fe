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
import { clone, h } from './dom.js';
import { parseCell, robotRows } from './panel.js';

/** DH values typed into the panel: decimal metres within ±10 m. */
const LENGTH = { head: 'value', unit: 'm', lo: -10, hi: 10 };

const mm = (x) => (Math.abs(x) < 5e-7 ? '0.000' : x.toFixed(3));

/** The label of the DH row `link` (1-based; branches after the main chain). */
function rowLabel(pg, link) {
  return robotRows(pg.robotSpec ?? { joints: [] })[link - 1]?.label ?? String(link);
}

/** A controller without pinned points (for a new robot, whose rows differ). */
export function withoutPins(controller) {
  if (!controller?.pinned?.length && controller?.selection !== 'pinned') return controller;
  return { ...controller, pinned: [], selection: controller.selection === 'pinned' ? 'perObstacle' : controller.selection };
}

export const pinMethods = {
  /** The pinned points of the scene (DH values). */
  pinnedPoints() {
    return this.scenario?.controller?.pinned ?? [];
  },

  /** Turns Pin mode on or off (`on` omitted: toggles). */
  setPinMode(on) {
    this.pinMode = on === undefined ? !this.pinMode : Boolean(on);
    this.panel?.pinMode.setAttribute('aria-pressed', String(this.pinMode));
    this.canvas.classList.toggle('pinning', this.pinMode);
    // A drawer panel (narrow widgets) would cover the arm: close it.
    if (this.pinMode && this.container.classList.contains('panel-open')) {
      this.container.classList.remove('panel-open');
      this.root.querySelector?.('#panel-toggle')?.setAttribute('aria-expanded', 'false');
    }
    if (this.pinMode) this.hint('Pin mode: click a link of the arm to pin a control point (P or Escape to stop)');
    this.setStatus(this.pinMode ? 'Pin mode: click a link of the arm to pin a control point there.' : 'Pin mode off.');
  },

  /**
   * Pins the skeleton's point under canvas pixel `px` (drawing-buffer
   * pixels). Returns the library's pick, or null when no link is under it
   * or the point was refused.
   */
  pinAt(px) {
    const ray = this.viewer.rayAt(px[0], px[1]);
    const hit = this.guard(() => this.world.pickSkeleton(ray.origin, ray.direction));
    if (!hit) {
      this.hint('No link of the arm under the pointer');
      return null;
    }
    return this.pin({ link: hit.link, d: hit.d, a: hit.a }) ? hit : null;
  },

  /** Adds a pinned point and selects `pinned`; false (message shown) when refused. */
  pin(point) {
    const pinned = [...this.pinnedPoints(), point];
    const current = this.scenario.controller?.selection;
    if (current && current !== 'pinned') this.selectionBeforePin = current;
    if (!this.applyPins(pinned, 'pinned')) return false;
    this.setStatus(`Pinned a control point on link ${rowLabel(this, point.link)} (d′ ${mm(point.d)} m, a′ ${mm(point.a)} m); selection: pinned.`);
    return true;
  },

  /** Removes pinned point `k`; the last one gone, the selection goes back to the one before. */
  unpin(k) {
    const points = this.pinnedPoints();
    if (k < 0 || k >= points.length) return false;
    const pinned = points.filter((_, i) => i !== k);
    const current = this.scenario.controller?.selection;
    const selection = pinned.length || current !== 'pinned' ? current : (this.selectionBeforePin ?? 'perObstacle');
    if (!this.applyPins(pinned, selection)) return false;
    this.setStatus(pinned.length ? `Removed pinned point ${k + 1}.` : `Removed the last pinned point; selection: ${selection}.`);
    // Keep the keyboard in the list.
    const items = this.panel?.pinnedList.querySelectorAll('li');
    (items?.[Math.min(k, pinned.length - 1)] ?? this.panel?.pinMode)?.focus();
    return true;
  },

  /** Gives the world `pinned` and `selection`; on refusal nothing changes and the reason is shown. */
  applyPins(pinned, selection) {
    const box = this.panel?.pinMessage;
    const partial = { pinned: clone(pinned), selection };
    const ok = this.guard(() => { this.world.setController(partial); return true; }, box);
    if (!ok) return false;
    this.scenario.controller = { ...(this.scenario.controller ?? {}), ...partial };
    this.forgetShareLink();
    this.edited = true;
    if (this.panel) this.panel.selection.value = selection;
    this.refreshPinned();
    return true;
  },

  /** Pins the DH values typed in the panel (checked first; refused in place). */
  pinTyped() {
    const p = this.panel;
    const link = Number(p.pinLink.value);
    const values = {};
    const problems = [];
    for (const [k, input] of [['d', p.pinD], ['a', p.pinA]]) {
      const { value, error } = parseCell(input.value, LENGTH);
      input.setAttribute('aria-invalid', error ? 'true' : 'false');
      if (error) problems.push(`${k}′ ${error}`);
      else values[k] = value;
    }
    if (problems.length) {
      p.pinMessage.textContent = problems.join('\n');
      return false;
    }
    return this.pin({ link, d: values.d, a: values.a });
  },

  /** Rebuilds the list of pinned points and the link menu of the typed entry. */
  refreshPinned() {
    const p = this.panel;
    if (!p) return;
    const points = this.pinnedPoints();
    const active = (this.scenario.controller?.selection ?? 'perObstacle') === 'pinned';
    p.pinnedList.replaceChildren(...points.map((pt, k) => {
      const text = `${k + 1}. link ${rowLabel(this, pt.link)} · d′ ${mm(pt.d)} · a′ ${mm(pt.a)} m`;
      const remove = h('button', { type: 'button', class: 'remove', 'aria-label': `remove pinned point ${k + 1}`, title: 'remove (Delete)',
        onclick: () => this.unpin(k) }, 'Remove');
      return h('li', { tabindex: '0', 'aria-label': `pinned point ${k + 1}: link ${rowLabel(this, pt.link)}, d′ ${mm(pt.d)} m, a′ ${mm(pt.a)} m`,
        onkeydown: (e) => {
          if (e.target !== e.currentTarget || (e.key !== 'Delete' && e.key !== 'Backspace')) return;
          e.preventDefault();
          e.stopPropagation();
          this.unpin(k);
        } }, h('span', {}, text), remove);
    }));
    p.pinnedEmpty.hidden = points.length > 0;
    p.pinnedInactive.hidden = points.length === 0 || active;
    const rows = robotRows(this.robotSpec ?? { joints: [] });
    const chosen = p.pinLink.value;
    p.pinLink.replaceChildren(...rows.map((r, i) => h('option', { value: String(i + 1) }, `link ${r.label}`)));
    if (chosen && Number(chosen) <= rows.length) p.pinLink.value = chosen;
  },

  /** The panel's "Pinned control points" section (its elements). */
  pinSection() {
    const pg = this;
    const p = pg.panel;
    p.pinMode = h('button', { type: 'button', id: 'pin-mode', 'aria-pressed': 'false', title: 'then click a link of the arm (key P)',
      onclick: () => pg.setPinMode() }, 'Pin by clicking (P)');
    p.pinnedList = h('ul', { class: 'pinned-points', id: 'pinned-list', 'aria-label': 'pinned control points' });
    p.pinnedEmpty = h('p', { class: 'hint', id: 'pinned-empty' }, 'None yet. Press "Pin by clicking" (or P) and click a link of the arm, or type DH values below.');
    p.pinnedInactive = h('p', { class: 'hint', id: 'pinned-inactive', hidden: true }, 'Used when the selection is pinned.');
    p.pinLink = h('select', { id: 'pin-link', 'aria-label': 'pinned point link' });
    const value = (id, label) => h('input', { id, value: '0', inputmode: 'decimal', 'aria-label': label, title: `${label} (m)`, style: 'width: 4.2rem' });
    p.pinD = value('pin-d', 'd′');
    p.pinA = value('pin-a', 'a′');
    p.pinMessage = h('div', { class: 'message', id: 'pin-message', role: 'status' });
    return [
      h('h3', {}, 'Pinned control points'),
      h('div', { class: 'row' }, p.pinMode),
      p.pinnedList, p.pinnedEmpty, p.pinnedInactive,
      h('div', { class: 'row' }, p.pinLink, 'd′', p.pinD, 'a′', p.pinA,
        h('button', { type: 'button', id: 'pin-add', onclick: () => pg.pinTyped() }, 'Pin')),
      p.pinMessage,
    ];
  },
};
