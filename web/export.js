// The run so far, as files a person can plot on their own: one sample per
// drawn frame (time, joints, joint velocities, clearance, control points)
// and every event, as CSV (one row per sample, events in the row of the
// sample they precede) or as JSON (`{ joints, samples, events }`).

/** Samples kept at most (about an hour at 60 frames a second). */
const MAX_SAMPLES = 200_000;

const csvCell = (x) => {
  if (x === undefined || x === null || (typeof x === 'number' && !Number.isFinite(x))) return '';
  const s = String(x);
  return /[",\n]/.test(s) ? `"${s.replaceAll('"', '""')}"` : s;
};

export class TraceRecorder {
  constructor() {
    this.clear();
  }

  clear() {
    this.samples = [];
    this.eventList = [];
  }

  /** Records one world state (`World.state()`). */
  push(state) {
    if (this.samples.length >= MAX_SAMPLES) return;
    this.samples.push({
      t: state.t,
      q: Array.from(state.q ?? []),
      qdot: Array.from(state.qdot ?? []),
      minClearance: Number.isFinite(state.minClearance) ? state.minClearance : null,
      stopped: Boolean(state.stopped),
      controlPoints: (state.controlPoints ?? []).map((c) => ({
        obstacle: c.obstacle, link: c.link, d: c.d, a: c.a, distance: c.distance, position: c.position, transitioning: Boolean(c.transitioning),
      })),
    });
  }

  /** Records events (`{ t, kind, … }`). */
  events(list) {
    for (const e of list) this.eventList.push({ ...e });
  }

  /** The trace as JSON text; `joints` names the columns of q. */
  json(joints) {
    return `${JSON.stringify({ joints, samples: this.samples, events: this.eventList }, null, 1)}\n`;
  }

  /** The trace as CSV text: a header, then one row per sample. */
  csv(joints) {
    const cps = Math.max(1, ...this.samples.map((s) => s.controlPoints.length));
    const header = ['t', ...joints.map((j) => `q${j}`), ...joints.map((j) => `qdot${j}`), 'min_clearance', 'stopped', 'control_points'];
    for (let k = 1; k <= cps; k++) header.push(...['obstacle', 'link', 'd', 'a', 'distance', 'x', 'y', 'z'].map((f) => `cp${k}_${f}`));
    header.push('events');
    const lines = [header.join(',')];
    let e = 0;
    for (const s of this.samples) {
      const kinds = [];
      while (e < this.eventList.length && this.eventList[e].t <= s.t + 1e-12) kinds.push(this.eventList[e++].kind);
      const row = [s.t, ...joints.map((_, i) => s.q[i]), ...joints.map((_, i) => s.qdot[i]), s.minClearance, s.stopped ? 1 : 0, s.controlPoints.length];
      for (let k = 0; k < cps; k++) {
        const c = s.controlPoints[k];
        row.push(...(c ? [c.obstacle, c.link, c.d, c.a, c.distance, ...(c.position ?? [])] : ['', '', '', '', '', '', '', '']));
      }
      row.push(kinds.join(';'));
      lines.push(row.map(csvCell).join(','));
    }
    return `${lines.join('\n')}\n`;
  }

  /** Offers the trace as a file download (`format`: "csv" or "json"). */
  download(format, joints, name) {
    const text = format === 'csv' ? this.csv(joints) : this.json(joints);
    const blob = new Blob([text], { type: format === 'csv' ? 'text/csv' : 'application/json' });
    const url = URL.createObjectURL(blob);
    const a = document.createElement('a');
    a.href = url;
    a.download = `${String(name).replace(/[^A-Za-z0-9_-]+/g, '-').replace(/^-|-$/g, '') || 'run'}-trace.${format}`;
    a.click();
    setTimeout(() => URL.revokeObjectURL(url), 1000);
    return text;
  }
}
