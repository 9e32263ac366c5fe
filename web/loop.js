// The frame loop: each animation frame steps the world by the time it
// owes (`SimClock`), reads its state when anything changed, draws, and
// feeds the trace, the plots, the HUD and the event feed.
//
// Owns: the clock, the frame counter, whether a refresh is due after a
// seek. Interface: `sim`, `viewer()`, `drawWorld()`, the parts it feeds
// (`readouts`, `plots`, `trace`, `events`), `running()`, `speed()`,
// `offscreen()`, `beforeSteps()` (a live person's latest frame into the
// world) and `onError(message)` (the loop stopped).
import { errorText } from './dom.js';
import { SimClock } from './clock.js';

/** Frames between refreshes of the plots and the text over the view. */
const REFRESH_EVERY = 10;

export class FrameLoop {
  constructor(host) {
    this.host = host;
    this.clock = new SimClock();
    this.frames = 0;
    this.seekPending = false;
    this.stopped = false;
  }

  /** Runs the loop; resolves once the first frames are drawn. */
  run() {
    let first;
    const drawn = new Promise((resolve) => { first = resolve; });
    const frame = (now) => {
      if (this.stopped) return;
      try {
        this.frame(now);
      } catch (err) {
        this.host.onError(`The playground stopped: ${errorText(err)}`);
        return;
      }
      if (this.frames === 2) first();
      requestAnimationFrame(frame);
    };
    requestAnimationFrame(frame);
    return drawn;
  }

  stop() {
    this.stopped = true;
  }

  frame(now) {
    const { sim, readouts } = this.host;
    const dt = sim.scenario.dt;
    const t0 = performance.now();
    this.host.beforeSteps?.();
    const steps = this.clock.stepsDue(this.clock.since(now), dt, this.host.speed(), this.host.running() && !this.host.offscreen());
    // One call per frame where the binding offers it.
    if (steps > 0 && typeof sim.world.advance === 'function') sim.world.advance(dt, steps);
    else for (let i = 0; i < steps; i++) sim.world.step(dt);
    const t1 = performance.now();
    // The viewer redraws only when something changed (a step, an edit, the camera).
    const changed = steps > 0 || sim.edited;
    if (changed) {
      // Only the events not shown yet are copied out.
      sim.state = sim.world.state(sim.seenEvents);
      this.host.drawWorld();
    }
    sim.edited = false;
    this.host.viewer().render();
    const t2 = performance.now();
    this.frames += 1;
    readouts.droppedS = this.clock.droppedS;
    readouts.wallS = this.clock.wallS;
    readouts.measure(now, steps, t1 - t0, t2 - t1);
    if (steps > 0) this.record();
    if (changed) this.showEvents();
    // Plots, the text over the view and the event feed are refreshed
    // together, six times a second: enough to read, and on software
    // rendering every frame in which anything but the 3D canvas changes
    // costs a full composite (a stop is shown at once: EventFeed.queue).
    if (this.frames % REFRESH_EVERY === 0 || (!this.host.running() && changed) || this.seekPending) {
      this.seekPending = false;
      this.host.plots.draw();
      readouts.refresh();
      this.host.events.flush();
    }
  }

  /** The state of this frame into the trace and the plots. */
  record() {
    const sim = this.host.sim;
    this.host.trace.push(sim.state);
    this.host.plots.record(sim.state, sim.robotSpec?.joints ?? [], sim.influence());
  }

  /** The events not shown yet, to the feed and the trace. */
  showEvents() {
    const sim = this.host.sim;
    // `state(since)` returns the events from index `since` on (a binding
    // without the cursor returns them all).
    let events = sim.state.events ?? [];
    const total = typeof sim.world.eventCount === 'number' ? sim.world.eventCount : events.length;
    if (events.length === total) events = events.slice(sim.seenEvents);
    this.host.events.queue(events);
    this.host.trace.events(events);
    sim.seenEvents = total;
  }
}
