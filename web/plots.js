// Time plots on 2D canvases, linked to the simulation time: a window of the
// last `span` seconds, a cursor at the current time, one line per series.

const PALETTE = ['#c0392b', '#2e86c1', '#27ae60', '#8e44ad', '#d68910', '#16a085', '#7f8c8d', '#e84393', '#34495e'];

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
    /** @type {Map<string, { t: number[], v: number[], color: string }>} */
    this.series = new Map();
    this.now = 0;
  }

  clear() {
    this.series.clear();
    this.now = 0;
  }

  /** Adds the value of series `name` at time `t` (s); non-finite values break the line. */
  push(name, t, value) {
    let s = this.series.get(name);
    if (!s) {
      s = { t: [], v: [], color: PALETTE[this.series.size % PALETTE.length] };
      this.series.set(name, s);
    }
    s.t.push(t);
    s.v.push(value);
    // Keep twice the visible window.
    const cut = s.t.findIndex((x) => x >= t - 2 * this.span);
    if (cut > 256) {
      s.t.splice(0, cut);
      s.v.splice(0, cut);
    }
    this.now = Math.max(this.now, t);
  }

  /** Plain copy of the data (for tests and export). */
  data() {
    const out = {};
    for (const [name, s] of this.series) out[name] = { t: [...s.t], v: [...s.v] };
    return out;
  }

  draw() {
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
    ctx.clearRect(0, 0, W, H);
    ctx.fillStyle = '#fff';
    ctx.fillRect(0, 0, W, H);
    const left = 38;
    const right = 6;
    const top = 16;
    const bottom = 14;
    const t1 = Math.max(this.now, this.span);
    const t0 = t1 - this.span;
    let lo = Infinity;
    let hi = -Infinity;
    for (const s of this.series.values()) {
      for (let i = 0; i < s.t.length; i++) {
        if (s.t[i] < t0 || !Number.isFinite(s.v[i])) continue;
        lo = Math.min(lo, s.v[i]);
        hi = Math.max(hi, s.v[i]);
      }
    }
    if (!Number.isFinite(lo)) {
      lo = 0;
      hi = 1;
    }
    if (this.min !== undefined && lo >= this.min) lo = this.min;
    if (hi - lo < 1e-6) {
      hi += 0.5;
      lo -= 0.5;
    }
    const pad = 0.05 * (hi - lo);
    lo -= pad;
    hi += pad;
    const x = (t) => left + ((t - t0) / (t1 - t0)) * (W - left - right);
    const y = (v) => top + (1 - (v - lo) / (hi - lo)) * (H - top - bottom);

    ctx.font = '10px system-ui, sans-serif';
    ctx.fillStyle = '#334';
    ctx.fillText(`${this.title} (${this.unit})`, left, 11);
    ctx.strokeStyle = '#e3e6ec';
    ctx.lineWidth = 1;
    ctx.fillStyle = '#667';
    for (const v of [lo + pad, (lo + hi) / 2, hi - pad]) {
      ctx.beginPath();
      ctx.moveTo(left, y(v));
      ctx.lineTo(W - right, y(v));
      ctx.stroke();
      ctx.fillText(formatTick(v), 2, y(v) + 3);
    }
    if (lo < 0 && hi > 0) {
      ctx.strokeStyle = '#b0b6c2';
      ctx.beginPath();
      ctx.moveTo(left, y(0));
      ctx.lineTo(W - right, y(0));
      ctx.stroke();
    }
    ctx.fillText(`${t0.toFixed(1)} s`, left, H - 2);
    ctx.fillText(`${t1.toFixed(1)} s`, W - right - 30, H - 2);

    let legendX = left + ctx.measureText(`${this.title} (${this.unit})`).width + 10;
    for (const [name, s] of this.series) {
      ctx.strokeStyle = s.color;
      ctx.lineWidth = 1.5;
      ctx.beginPath();
      let pen = false;
      for (let i = 0; i < s.t.length; i++) {
        if (s.t[i] < t0 || !Number.isFinite(s.v[i])) {
          pen = false;
          continue;
        }
        if (pen) ctx.lineTo(x(s.t[i]), y(s.v[i]));
        else ctx.moveTo(x(s.t[i]), y(s.v[i]));
        pen = true;
      }
      ctx.stroke();
      if (legendX < W - 40) {
        ctx.fillStyle = s.color;
        ctx.fillText(name, legendX, 11);
        legendX += ctx.measureText(name).width + 8;
      }
    }
    // The cursor at the current simulation time.
    ctx.strokeStyle = '#1d2330';
    ctx.setLineDash([3, 3]);
    ctx.beginPath();
    ctx.moveTo(x(this.now), top);
    ctx.lineTo(x(this.now), H - bottom);
    ctx.stroke();
    ctx.setLineDash([]);
  }
}

function formatTick(v) {
  const a = Math.abs(v);
  if (a >= 100) return v.toFixed(0);
  if (a >= 1) return v.toFixed(2);
  return v.toFixed(3);
}
