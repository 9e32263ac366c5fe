// The plots under the view, fed from the state of every drawn frame:
// clearance (minimum and per control point, the influence distance as a
// reference), the active control point's DH values (the paper's fig. 5)
// and the joint velocities (the lowest speed limit as a reference).
//
// Owns: the three `TimePlot`s and which of them are shown. No interface:
// the Playground hands it each state with what to read it against.
import { h } from './dom.js';
import { TimePlot } from './plots.js';

export class PlotStrip {
  /** @param {string[]} wanted the plots to show (`clearance`, `dh`, `qdot`) */
  constructor(wanted) {
    this.plots = {
      clearance: new TimePlot(h('canvas', { id: 'plot-clearance' }), { title: 'clearance', unit: 'm', min: 0 }),
      dh: new TimePlot(h('canvas', { id: 'plot-dh' }), { title: 'control point DH values', unit: 'm' }),
      qdot: new TimePlot(h('canvas', { id: 'plot-qdot' }), { title: 'joint velocities', unit: 'rad/s' }),
    };
    this.shown = wanted.filter((k) => this.plots[k]);
    this.element = h('div', { class: 'plots' }, this.shown.map((k) => this.plots[k].element));
  }

  /** Empties every plot and sets the reference lines: the influence distance, the lowest speed limit. */
  clear(influence, vmax) {
    for (const plot of Object.values(this.plots)) plot.clear();
    this.plots.clearance.setReferences([{ v: influence, label: 'influence distance' }]);
    this.plots.qdot.setReferences([{ v: vmax, label: 'lowest speed limit' }, { v: -vmax }]);
  }

  /** Moves every plot's cursor to time `t` (s). */
  mark(t) {
    for (const plot of Object.values(this.plots)) plot.mark(t);
  }

  draw() {
    for (const key of this.shown) this.plots[key].draw();
  }

  /** Adds the samples of state `s` (of a robot with `joints`, the influence distance `influence`). */
  record(s, joints, influence) {
    const t = s.t;
    const clearance = this.plots.clearance;
    // Beyond the influence distance the world does not measure: the line
    // stays at the influence distance, drawn dashed, and the HUD says "beyond".
    const far = !Number.isFinite(s.minClearance);
    clearance.push('min', t, far ? influence : s.minClearance, { far });
    // One line per obstacle (and per control point on it), so colours stay with their obstacle.
    const seen = new Map();
    for (const cp of s.controlPoints) {
      const k = (seen.get(cp.obstacle) ?? 0) + 1;
      seen.set(cp.obstacle, k);
      const name = k === 1 ? cp.obstacle : `${cp.obstacle} #${k}`;
      clearance.push(name, t, cp.distance, { sigma: cp.sigma?.distance });
      // A human's line carries the name of its closest part (the legend shows the latest).
      if (cp.part) clearance.label(name, `${cp.obstacle}: ${cp.part.split(':').pop()}`);
    }
    // Fig. 5: the DH table of the control point's shorter manipulator (the
    // library's `table`), main-chain rows; the `d` rows only for robots
    // with a non-zero d.
    const cp = s.controlPoints.find((c) => c.transitioning) ?? s.controlPoints[0];
    const anyD = joints.some((j) => j.d !== 0);
    joints.forEach((_, i) => {
      const row = i + 1;
      const r = cp?.table?.[i] ?? { d: NaN, a: NaN };
      // The control point's own row carries the propagated σ of its witness as a band.
      const sd = (x) => ({ sigma: cp && row === cp.link ? x : 0 });
      this.plots.dh.push(`a${row}`, t, r.a, sd(cp?.sigma?.a));
      if (anyD) this.plots.dh.push(`d${row}`, t, r.d, sd(cp?.sigma?.d));
    });
    Array.from(s.qdot ?? []).forEach((v, i) => this.plots.qdot.push(`q̇${i + 1}`, t, v));
  }
}
