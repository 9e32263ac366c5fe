// Time plots linked to the simulation time: the last `span` seconds, a
// cursor at the current time, one line per series in a colour of its own, a
// legend that wraps and toggles lines, reference lines (influence distance,
// joint limits), a readout under the pointer and a mark set from the event
// log. Text is 12 px, dark on white (contrast above 7:1).

/** Fifteen colours that stay apart from each other on white (lines, not text). */
export const COLOURS = ['#1f77b4', '#d62728', '#2ca02c', '#9467bd', '#ff7f0e', '#17becf', '#8c564b', '#e377c2',
  '#7f7f7f', '#bcbd22', '#393b79', '#ad494a', '#637939', '#843c39', '#5254a3'];
const TEXT = '#1d2330';
const MUTED = '#4a5160';
/** Reference lines (influence distance, limits) and their labels. */
const REFERENCE = '#6b4f00';
/** Every colour text is drawn in on the plots' white (tests check the contrast). */
export const TEXT_COLOURS = { text: TEXT, muted: MUTED, reference: REFERENCE };
/** The size of every text on the plots (px). */
export const FONT_PX = 12;
/** Seconds of history kept (for the mark and the readout). */
const KEEP = 60;

const el = (tag, cls, text) => {
  const e = document.createElement(tag);
  if (cls) e.className = cls;
  if (text !== undefined) e.textContent = text;
  return e;
};

export class TimePlot {
  /**
   * @param {HTMLCanvasElement} canvas
   * @param {{ title: string, unit: string, span?: number, min?: number }} options
   *   `min`: a floor for the value axis (e.g. 0 for clearances) when data allow.
   */
  constructor(canvas, { title, unit, span = 5, min } = {}) {
    this.canvas = canvas;
    this.title = title;
    this.unit = unit;
    this.span = span;
    this.min = min;
    /** @type {Map<string, { t: number[], v: number[], far: boolean[], color: string, hidden: boolean, key: HTMLElement }>} */
    this.series = new Map();
    this.refs = [];
    this.now = 0;
    this.marked = null;
    this.hover = null;
    this.legend = el('div', 'legend');
    this.legend.setAttribute('aria-label', `${title}: lines`);
    const head = el('div', 'plot-head');
    head.append(el('span', 'plot-title', `${title} (${unit})`), this.legend);
    this.element = el('figure', 'plot');
    this.element.id = `${canvas.id}-figure`;
    canvas.setAttribute('role', 'img');
    canvas.setAttribute('aria-label', `${title} over time`);
    this.element.append(head, canvas);
    canvas.addEventListener('pointermove', (e) => {
      const r = canvas.getBoundingClientRect();
      this.hover = e.clientX - r.left;
      this.draw();
    });
    canvas.addEventListener('pointerleave', () => {
      this.hover = null;
      this.draw();
    });
  }

  clear() {
    this.series.clear();
    this.legend.replaceChildren();
    this.now = 0;
    this.marked = null;
  }

  /** Horizontal reference lines: `[{ v, label }]` (e.g. the influence distance, ± a speed limit). */
  setReferences(refs) {
    this.refs = refs.filter((r) => Number.isFinite(r.v));
  }

  /** Marks time `t` (s) with a second cursor and shows the window around it. */
  mark(t) {
    this.marked = t;
  }

  /**
   * Adds the value of series `name` at time `t` (s); non-finite values break
   * the line; `far` draws the point's segment dashed (a value standing for
   * "at least this much"); `sigma` draws a band of ±sigma around the line
   * (a propagated standard deviation).
   */
  push(name, t, value, { far = false, sigma = 0 } = {}) {
    let s = this.series.get(name);
    if (!s) {
      s = { t: [], v: [], far: [], sd: [], color: COLOURS[this.series.size % COLOURS.length], hidden: false };
      s.key = this.legendKey(name, s);
      this.series.set(name, s);
    }
    s.t.push(t);
    s.v.push(value);
    s.far.push(far);
    s.sd.push(Number.isFinite(sigma) && sigma > 0 ? sigma : 0);
    const cut = s.t.findIndex((x) => x >= t - KEEP);
    if (cut > 1024) {
      s.t.splice(0, cut);
      s.v.splice(0, cut);
      s.far.splice(0, cut);
      s.sd.splice(0, cut);
    }
    this.now = Math.max(this.now, t);
  }

  /**
   * Names line `name` `text` in the legend (e.g. which part of a human is
   * closest), from the next `draw` on: a person's nearest part can change
   * every frame, and each change of the legend's text lays out and paints
   * the page again (on software rendering half the frames of human-panda
   * did so once the person stood by the arm).
   */
  label(name, text) {
    const s = this.series.get(name);
    if (s) s.label = text;
  }

  /** Writes the labels set since the last `draw` into the legend. */
  showLabels() {
    for (const s of this.series.values()) {
      const node = s.key.lastChild;
      if (s.label !== undefined && node.textContent !== s.label) node.textContent = s.label;
    }
  }

  legendKey(name, s) {
    const key = el('button', 'key');
    key.type = 'button';
    key.setAttribute('aria-pressed', 'true');
    key.title = `show or hide ${name}`;
    const swatch = el('span', 'swatch');
    swatch.style.background = s.color;
    key.append(swatch, document.createTextNode(name));
    key.addEventListener('click', () => {
      s.hidden = !s.hidden;
      key.setAttribute('aria-pressed', String(!s.hidden));
      this.draw();
    });
    this.legend.append(key);
    return key;
  }

  /** Plain copy of the data (for tests and export). */
  data() {
    const out = {};
    for (const [name, s] of this.series) out[name] = { t: [...s.t], v: [...s.v] };
    return out;
  }

  /** The time window shown: the last `span` seconds, or around the mark. */
  window() {
    if (this.marked !== null && (this.marked < this.now - this.span || this.marked > this.now)) {
      const t0 = Math.max(0, this.marked - this.span / 2);
      return [t0, t0 + this.span];
    }
    const t1 = Math.max(this.now, this.span);
    return [t1 - this.span, t1];
  }

  range(t0, t1) {
    let lo = Infinity;
    let hi = -Infinity;
    for (const s of this.series.values()) {
      if (s.hidden) continue;
      for (let i = 0; i < s.t.length; i++) {
        if (s.t[i] < t0 || s.t[i] > t1 || !Number.isFinite(s.v[i])) continue;
        lo = Math.min(lo, s.v[i]);
        hi = Math.max(hi, s.v[i]);
      }
    }
    for (const r of this.refs) {
      lo = Math.min(lo, r.v);
      hi = Math.max(hi, r.v);
    }
    if (!Number.isFinite(lo)) [lo, hi] = [0, 1];
    if (this.min !== undefined && lo >= this.min) lo = this.min;
    if (hi - lo < 1e-6) [lo, hi] = [lo - 0.5, hi + 0.5];
    const pad = 0.06 * (hi - lo);
    return [lo - pad, hi + pad];
  }

  draw() {
    this.showLabels();
    const { canvas } = this;
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(canvas.clientWidth * dpr));
    const h = Math.max(1, Math.round(canvas.clientHeight * dpr));
    if (canvas.width !== w || canvas.height !== h) Object.assign(canvas, { width: w, height: h });
    // A CPU canvas: plots are small, and a GPU-backed 2D canvas is far
    // slower than the CPU one where the GPU is emulated in software.
    const ctx = canvas.getContext('2d', { willReadFrequently: true });
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    const W = w / dpr;
    const H = h / dpr;
    ctx.fillStyle = '#fff';
    ctx.fillRect(0, 0, W, H);
    const box = { left: 46, right: 8, top: 6, bottom: 18 };
    const [t0, t1] = this.window();
    const [lo, hi] = this.range(t0, t1);
    const x = (t) => box.left + ((t - t0) / (t1 - t0)) * (W - box.left - box.right);
    const y = (v) => box.top + (1 - (v - lo) / (hi - lo)) * (H - box.top - box.bottom);
    this.axes(ctx, { W, H, box, t0, t1, lo, hi, x, y });
    for (const s of this.series.values()) if (!s.hidden) this.line(ctx, s, t0, t1, x, y);
    const cursor = (t, dash, colour) => {
      if (t < t0 || t > t1) return;
      ctx.strokeStyle = colour;
      ctx.setLineDash(dash);
      ctx.beginPath();
      ctx.moveTo(x(t), box.top);
      ctx.lineTo(x(t), H - box.bottom);
      ctx.stroke();
      ctx.setLineDash([]);
    };
    cursor(this.now, [3, 3], TEXT);
    if (this.marked !== null) cursor(this.marked, [], '#b3261e');
    if (this.hover !== null && this.hover > box.left) this.readout(ctx, t0 + ((this.hover - box.left) / (W - box.left - box.right)) * (t1 - t0), x, W);
  }

  axes(ctx, { W, H, box, t0, t1, lo, hi, y }) {
    ctx.font = `${FONT_PX}px system-ui, sans-serif`;
    ctx.lineWidth = 1;
    const pad = 0.06 / 1.12 * (hi - lo);
    for (const v of [lo + pad, (lo + hi) / 2, hi - pad]) {
      ctx.strokeStyle = '#e3e6ec';
      ctx.beginPath();
      ctx.moveTo(box.left, y(v));
      ctx.lineTo(W - box.right, y(v));
      ctx.stroke();
      ctx.fillStyle = MUTED;
      ctx.fillText(formatTick(v), 2, y(v) + 4);
    }
    if (lo < 0 && hi > 0) {
      ctx.strokeStyle = '#9aa1ad';
      ctx.beginPath();
      ctx.moveTo(box.left, y(0));
      ctx.lineTo(W - box.right, y(0));
      ctx.stroke();
    }
    for (const r of this.refs) {
      ctx.strokeStyle = REFERENCE;
      ctx.setLineDash([6, 4]);
      ctx.beginPath();
      ctx.moveTo(box.left, y(r.v));
      ctx.lineTo(W - box.right, y(r.v));
      ctx.stroke();
      ctx.setLineDash([]);
      if (r.label) {
        ctx.fillStyle = REFERENCE;
        ctx.fillText(r.label, W - box.right - ctx.measureText(r.label).width - 2, y(r.v) - 3);
      }
    }
    ctx.fillStyle = MUTED;
    ctx.fillText(`${t0.toFixed(1)} s`, box.left, H - 4);
    const end = `${t1.toFixed(1)} s`;
    ctx.fillText(end, W - box.right - ctx.measureText(end).width, H - 4);
  }

  /** The ±σ band of a series, where it has one (translucent, under its line). */
  band(ctx, s, t0, t1, x, y) {
    const run = [];
    const flush = () => {
      if (run.length > 1) {
        ctx.beginPath();
        run.forEach((i, k) => (k ? ctx.lineTo : ctx.moveTo).call(ctx, x(s.t[i]), y(s.v[i] + s.sd[i])));
        for (let k = run.length - 1; k >= 0; k--) ctx.lineTo(x(s.t[run[k]]), y(s.v[run[k]] - s.sd[run[k]]));
        ctx.closePath();
        ctx.fill();
      }
      run.length = 0;
    };
    ctx.fillStyle = s.color;
    ctx.globalAlpha = 0.2;
    for (let i = 0; i < s.t.length; i++) {
      if (s.t[i] >= t0 && s.t[i] <= t1 && Number.isFinite(s.v[i]) && s.sd[i] > 0) run.push(i);
      else flush();
    }
    flush();
    ctx.globalAlpha = 1;
  }

  line(ctx, s, t0, t1, x, y) {
    this.band(ctx, s, t0, t1, x, y);
    ctx.strokeStyle = s.color;
    ctx.lineWidth = 1.75;
    let pen = false;
    let dashed = null;
    for (let i = 0; i < s.t.length; i++) {
      if (s.t[i] < t0 || s.t[i] > t1 || !Number.isFinite(s.v[i])) {
        if (pen) ctx.stroke();
        pen = false;
        continue;
      }
      if (pen && dashed !== s.far[i]) {
        // The style changes: finish the line in its style and go on from here.
        ctx.lineTo(x(s.t[i]), y(s.v[i]));
        ctx.stroke();
        pen = false;
      }
      if (!pen) {
        dashed = s.far[i];
        ctx.setLineDash(dashed ? [2, 3] : []);
        ctx.beginPath();
        ctx.moveTo(x(s.t[i]), y(s.v[i]));
        pen = true;
      } else {
        ctx.lineTo(x(s.t[i]), y(s.v[i]));
      }
    }
    if (pen) ctx.stroke();
    ctx.setLineDash([]);
  }

  /** The values of the shown lines at time `t`, in a box by the pointer. */
  readout(ctx, t, x, W) {
    const rows = [`t ${t.toFixed(3)} s`];
    for (const [name, s] of this.series) {
      if (s.hidden || s.t.length === 0) continue;
      let i = s.t.findIndex((u) => u >= t);
      if (i < 0) i = s.t.length - 1;
      if (Math.abs(s.t[i] - t) > 0.1 || !Number.isFinite(s.v[i])) continue;
      rows.push(`${name} ${formatTick(s.v[i])}${s.far[i] ? '+' : ''}`);
      if (rows.length > 7) break;
    }
    const width = Math.max(...rows.map((r) => ctx.measureText(r).width)) + 10;
    const left = x(t) + width + 8 < W ? x(t) + 6 : x(t) - width - 6;
    ctx.fillStyle = 'rgba(255,255,255,0.94)';
    ctx.strokeStyle = '#9aa1ad';
    ctx.fillRect(left, 4, width, rows.length * 15 + 4);
    ctx.strokeRect(left, 4, width, rows.length * 15 + 4);
    ctx.fillStyle = TEXT;
    rows.forEach((r, k) => ctx.fillText(r, left + 5, 17 + k * 15));
    ctx.strokeStyle = MUTED;
    ctx.beginPath();
    ctx.moveTo(x(t), 0);
    ctx.lineTo(x(t), ctx.canvas.height);
    ctx.stroke();
  }
}

function formatTick(x) {
  const v = Math.abs(x) < 5e-13 ? 0 : x;
  const a = Math.abs(v);
  if (a >= 100) return v.toFixed(0);
  if (a >= 1) return v.toFixed(2);
  return v.toFixed(3);
}
