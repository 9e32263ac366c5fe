// What the widget reads out of the world for the person: the text over the
// view (the HUD: time, clearance, time to collision, control points) and
// the stats overlay (frame rate, steps per frame, time spent).
//
// Owns: the HUD and stats boxes and the frame statistics (`stats`).
// Interface: `sim` (the state and the scenario read), `running()`,
// `speed()`, `backend()` and `extra()` (lines of a live person's sensing).
import { h } from './dom.js';

export class Readouts {
  /**
   * @param {{ sim: import('./sim.js').Sim, running: () => boolean, speed: () => number, backend: () => string }} host
   */
  constructor(host) {
    this.host = host;
    this.hud = h('div', { class: 'hud', id: 'hud' });
    this.statsBox = h('div', { class: 'stats', id: 'stats', 'aria-hidden': 'true' });
    this.stats = { fps: 0, frameMs: 0, stepsPerFrame: 0, stepMs: 0, drawMs: 0 };
    this.frameTimes = [];
    this.droppedS = 0;
    this.wallS = 0;
  }

  /** One frame's figures: its timestamp, the steps it ran and the ms spent stepping and drawing. */
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
      droppedS: this.droppedS,
      wallS: this.wallS,
      backend: this.host.backend(),
    };
  }

  /** Writes the stats and the HUD from the last state read. */
  refresh() {
    const { sim } = this.host;
    const st = this.stats;
    this.statsBox.textContent = `${st.fps.toFixed(0)} fps  ${st.frameMs.toFixed(1)} ms/frame\n`
      + `${st.stepsPerFrame} steps/frame (${(1 / sim.scenario.dt).toFixed(0)} Hz × ${this.host.speed().toFixed(2)})\n`
      + `step ${st.stepMs.toFixed(2)} ms  draw ${st.drawMs.toFixed(2)} ms  ${this.host.backend() === 'webgpu' ? 'WebGPU' : 'WebGL2'}`;
    this.hud.textContent = [...hudLines(sim.state, this.host.running(), sim.influence()), ...(this.host.extra?.() ?? [])].join('\n');
  }

  /**
   * How much taller the HUD will get in a scene with a person (CSS px): a
   * fit on load would frame their head where the HUD reaches once it shows
   * the nearest human part, a line per obstacle sensed with error and three
   * control points (human-panda). The HUD's typical text then is laid out
   * in a hidden copy of the box, so that lines wrapped in a narrow view (a
   * phone's HUD is half of 390 px) count as the rows they take. Other
   * scenes are framed below the HUD as it is.
   */
  growth() {
    const obstacles = this.host.sim.scenario?.obstacles ?? [];
    const person = obstacles.find((o) => o.shape?.type === 'human');
    if (!person) return 0;
    const sensed = this.host.sim.scenario?.sensing ?? {};
    const cp = (near) => ({ link: 5, d: 0.277, a: -0.083, ...(near ? { part: `${person.id}:leftHand` } : {}),
      ...(near && Object.hasOwn(sensed, person.id) ? { sigma: { d: 0.005, a: 0.005 } } : {}) });
    const typical = {
      // The closest pair is not the person's (else the person's part is on
      // the clearance line, and there is no line for the nearest human part).
      t: 10, stopped: false, minClearance: 0.081, timeToCollision: 4.24,
      closestHuman: { part: `${person.id}:rightThigh`, distance: 0.18 },
      protection: { part: `${person.id}:rightThigh`, region: 'thigh', active: 'ssm', distance: 0.18, ssmBound: 0.85 },
      uncertainty: obstacles.filter((o) => Object.hasOwn(sensed, o.id)).map((o) => ({ obstacle: o.id, switchProbability: 0.3, sigma: 0.004 })),
      controlPoints: [cp(true), cp(false), cp(false)],
    };
    const copy = this.hud.cloneNode(false);
    copy.removeAttribute('id');
    copy.style.visibility = 'hidden';
    copy.textContent = hudLines(typical, true, this.host.sim.influence()).join('\n');
    this.hud.after(copy);
    const grown = copy.getBoundingClientRect().height - this.hud.getBoundingClientRect().height;
    copy.remove();
    return Math.max(0, grown);
  }
}

const ms = (x) => `${(x * 1000).toFixed(0)} mm`;

/** A streamed person whose data is stale (World.pushHumanFrame): the stale part with the largest margin,
 * grown at a person's speed, and the age of its data; or null. */
function staleLine(u) {
  const stale = Object.entries(u.stale ?? {});
  if (stale.length === 0) return null;
  const margin = (part) => u.partMargins?.[part] ?? 0;
  const [part, age] = stale.reduce((a, b) => (margin(b[0]) > margin(a[0]) ? b : a));
  return `${u.obstacle}: stale sensing, ${part} ${(age * 1000).toFixed(0)} ms old, margin ${ms(margin(part))}`;
}

/**
 * The text over the view: time and state, clearance, time to collision, the
 * protective bound in force for the nearest human part (with the arm's
 * effective mass towards it; every control point's is in the state), control
 * points.
 */
export function hudLines(s, running, influence) {
  const ttc = s.timeToCollision;
  let ttcText = '—  (nothing closing in)';
  if (Number.isFinite(ttc)) ttcText = ttc > 10 ? '> 10 s' : `${ttc.toFixed(2)} s`;
  const lines = [
    `t ${s.t.toFixed(3)} s${s.stopped ? '  STOPPED' : running ? '' : '  paused'}`,
    `min clearance ${Number.isFinite(s.minClearance) ? ms(s.minClearance) : `> ${ms(influence)} (influence)`}${s.closestPart ? `  (${s.closestPart})` : ''}`,
    `time to collision ${ttcText}`,
  ];
  // The nearest human part, when something else (two of the arm's own
  // links, another obstacle) is closer and the line above does not name it.
  const human = s.closestHuman;
  if (human && human.part !== s.closestPart) lines.push(`nearest human part ${human.part}  ${ms(human.distance)}`);
  // Which protective bound holds the approach to the nearest human part:
  // separation monitoring, or power and force limiting's contact speed.
  const p = s.protection;
  if (p) {
    const bound = p.active === 'pfl' ? p.contact.speed : p.ssmBound;
    // The arm's effective mass towards that part: power and force
    // limiting's own, else the nearest control point's on that part.
    const cpMass = s.controlPoints.find((cp) => cp.part === p.part && Number.isFinite(cp.effectiveMass))?.effectiveMass;
    const armMass = p.contact?.armMass ?? cpMass;
    const mass = armMass === undefined ? '' : `  arm ${armMass.toFixed(1)} kg`;
    lines.push(`${p.active} ${p.region} ≤ ${Math.max(0, bound).toFixed(2)} m/s${mass}`);
  }
  for (const u of s.uncertainty ?? []) {
    if (u.switchProbability > 0) lines.push(`${u.obstacle}: switch p ${u.switchProbability.toFixed(2)}  σ ${ms(u.sigma)}`);
    const stale = staleLine(u);
    if (stale) lines.push(stale);
  }
  s.controlPoints.slice(0, 3).forEach((cp, i) => {
    let text = `cp${i + 1} link ${cp.link}  d' ${cp.d.toFixed(3)}  a' ${cp.a.toFixed(3)} m${cp.part ? `  ← ${cp.part}` : ''}`;
    if (cp.sigma) text += `  ±${ms(Math.max(cp.sigma.d, cp.sigma.a))}`;
    if (cp.transitioning && cp.target) text += `\n    → link ${cp.target.link} (${cp.target.d.toFixed(3)}, ${cp.target.a.toFixed(3)})`;
    lines.push(text);
  });
  return lines;
}
