// The simulation's clock in the page: how many control steps each drawn
// frame owes the world (real time × speed), with the steps asked for one
// at a time while paused.
//
// Owns: the time not yet stepped (`acc`), the steps asked for while paused,
// the last frame's timestamp, the page's own clock (`wallS`) and the time
// dropped on long frames (`droppedS`). No interface: the Playground asks.
export class SimClock {
  constructor() {
    this.acc = 0;
    this.pendingSteps = 0;
    this.lastNow = undefined;
    this.wallS = 0;
    this.droppedS = 0;
  }

  /** Starts counting again from the next frame (a new scene, back on screen). */
  restart() {
    this.acc = 0;
  }

  /** Seconds since the last frame at `now` (ms; 0 for the first frame). */
  since(now) {
    const wall = this.lastNow === undefined ? 0 : (now - this.lastNow) / 1000;
    this.lastNow = now;
    return wall;
  }

  /**
   * How many control steps of `dt` this frame owes the simulation (`wall`
   * seconds since the last one, `speed` times real time, capped); only the
   * steps asked for while the simulation waits (`running` false).
   */
  stepsDue(wall, dt, speed, running) {
    const asked = this.pendingSteps;
    this.pendingSteps = 0;
    if (!running) return asked;
    // A frame longer than 100 ms (a busy machine, a background tab) does
    // not make the simulation race to catch up: the excess is dropped, and
    // counted (`droppedS`), so that real time is kept or the loss is known.
    // `wallS`: the page's own clock (frame timestamps × speed) while it
    // runs; simulated time plus `droppedS` follows it to within a step.
    this.wallS += wall * speed;
    this.droppedS += Math.max(0, wall - 0.1) * speed;
    this.acc += Math.min(wall, 0.1) * speed;
    let steps = Math.floor(this.acc / dt + 1e-9);
    const cap = Math.ceil(0.1 / dt);
    if (steps > cap) {
      steps = cap;
      this.droppedS += this.acc - cap * dt;
      this.acc = 0;
    } else {
      this.acc -= steps * dt;
    }
    return steps;
  }
}
