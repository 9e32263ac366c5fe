// What the widget reads out of the world each frame, as methods mixed into
// the Playground: the plots' samples, the events, the text over the view,
// and the plots' cursor moved to an event.

export const readoutMethods = {
  /** The influence distance in force (m): the scenario's or the library's default. */
  influence() {
    // The value in effect: the library's default when the scenario omits it.
    return this.world?.controller().influenceDistance ?? this.scenario.controller?.influenceDistance ?? 0.3;
  },

  record() {
    const s = this.state;
    const t = s.t;
    this.trace.push(s);
    // Beyond the influence distance the world does not measure: the line
    // stays at the influence distance, drawn dashed, and the HUD says "beyond".
    const far = !Number.isFinite(s.minClearance);
    this.plots.clearance.push('min', t, far ? this.influence() : s.minClearance, { far });
    // One line per obstacle (and per control point on it), so colours stay with their obstacle.
    const seen = new Map();
    for (const cp of s.controlPoints) {
      const k = (seen.get(cp.obstacle) ?? 0) + 1;
      seen.set(cp.obstacle, k);
      this.plots.clearance.push(k === 1 ? cp.obstacle : `${cp.obstacle} #${k}`, t, cp.distance, { sigma: cp.sigma?.distance });
      // A human's line carries the name of its closest part (the legend shows the latest).
      if (cp.part) this.plots.clearance.label(k === 1 ? cp.obstacle : `${cp.obstacle} #${k}`, `${cp.obstacle}: ${cp.part.split(':').pop()}`);
    }
    // Fig. 5: the DH table of the control point's shorter manipulator (the
    // library's `table`), main-chain rows; the `d` rows only for robots
    // with a non-zero d.
    const cp = s.controlPoints.find((c) => c.transitioning) ?? s.controlPoints[0];
    const joints = this.robotSpec?.joints ?? [];
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
  },

  showEvents() {
    // `state(since)` returns the events from index `since` on (a binding
    // without the cursor returns them all).
    let events = this.state.events ?? [];
    const total = typeof this.world.eventCount === 'number' ? this.world.eventCount : events.length;
    if (events.length === total) events = events.slice(this.seenEvents);
    this.events.queue(events);
    this.trace.events(events);
    this.seenEvents = total;
  },

  refreshHud() {
    const s = this.state;
    const st = this.stats;
    this.statsBox.textContent = `${st.fps.toFixed(0)} fps  ${st.frameMs.toFixed(1)} ms/frame\n`
      + `${st.stepsPerFrame} steps/frame (${(1 / this.scenario.dt).toFixed(0)} Hz × ${this.speed.toFixed(2)})\n`
      + `step ${st.stepMs.toFixed(2)} ms  draw ${st.drawMs.toFixed(2)} ms  ${this.backend === 'webgpu' ? 'WebGPU' : 'WebGL2'}`;
    this.hud.textContent = hudLines(s, this.running, this.influence()).join('\n');
  },

  /**
   * How much taller the HUD will get in a scene with a person (CSS px): a
   * fit on load would frame their head where the HUD reaches once it shows
   * the nearest human part, a line per obstacle sensed with error and three
   * control points (human-panda). The HUD's typical text then is laid out
   * in a hidden copy of the box, so that lines wrapped in a narrow view (a
   * phone's HUD is half of 390 px) count as the rows they take. Other
   * scenes are framed below the HUD as it is.
   */
  hudGrowth() {
    const obstacles = this.scenario?.obstacles ?? [];
    const person = obstacles.find((o) => o.shape?.type === 'human');
    if (!person) return 0;
    const sensed = this.scenario?.sensing ?? {};
    const cp = (near) => ({ link: 5, d: 0.277, a: -0.083, ...(near ? { part: `${person.id}:leftHand` } : {}),
      ...(near && Object.hasOwn(sensed, person.id) ? { sigma: { d: 0.005, a: 0.005 } } : {}) });
    const typical = {
      // The closest pair is not the person's (else the person's part is on
      // the clearance line, and there is no line for the nearest human part).
      t: 10, stopped: false, minClearance: 0.081, timeToCollision: 4.24,
      closestHuman: { part: `${person.id}:rightThigh`, distance: 0.18 },
      uncertainty: obstacles.filter((o) => Object.hasOwn(sensed, o.id)).map((o) => ({ obstacle: o.id, switchProbability: 0.3, sigma: 0.004 })),
      controlPoints: [cp(true), cp(false), cp(false)],
    };
    const copy = this.hud.cloneNode(false);
    copy.removeAttribute('id');
    copy.style.visibility = 'hidden';
    copy.textContent = hudLines(typical, true, this.influence()).join('\n');
    this.hud.after(copy);
    const grown = copy.getBoundingClientRect().height - this.hud.getBoundingClientRect().height;
    copy.remove();
    return Math.max(0, grown);
  },

  /** Moves the plots' cursor to time `t` (s) and pauses, so the moment can be read. */
  seek(t) {
    if (this.running) this.toggleRun();
    for (const plot of Object.values(this.plots)) plot.mark(t);
    this.seekPending = true;
    this.setStatus(`Plots marked at t = ${t.toFixed(3)} s.`);
  },
};

const ms = (x) => `${(x * 1000).toFixed(0)} mm`;

/** The text over the view: time and state, clearance, time to collision, control points. */
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
  for (const u of s.uncertainty ?? []) {
    if (u.switchProbability > 0) lines.push(`${u.obstacle}: switch p ${u.switchProbability.toFixed(2)}  σ ${ms(u.sigma)}`);
  }
  s.controlPoints.slice(0, 3).forEach((cp, i) => {
    let text = `cp${i + 1} link ${cp.link}  d' ${cp.d.toFixed(3)}  a' ${cp.a.toFixed(3)} m${cp.part ? `  ← ${cp.part}` : ''}`;
    if (cp.sigma) text += `  ±${ms(Math.max(cp.sigma.d, cp.sigma.a))}`;
    if (cp.transitioning && cp.target) text += `\n    → link ${cp.target.link} (${cp.target.d.toFixed(3)}, ${cp.target.a.toFixed(3)})`;
    lines.push(text);
  });
  return lines;
}
