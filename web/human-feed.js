// A live person in the world: keypoint frames from the camera or the
// sensor bridge, the latest kept and given to the world once per drawn
// frame, before its steps.
//
// The world takes a frame by `World.pushHumanFrame(id, { t, layout,
// keypoints, confidence })`, `t` on the world's clock: when it was
// captured. Its measured age on arrival (capture → pose → step, the median
// of the last frames) is the person's sensing latency, set by
// `World.setSensingLatency`: the world sees the person that long ago, so a
// frame is as old as it really is and the stale margins grow only past it.
// A build of the library without `pushHumanFrame` gets the frame's pose as
// the person's shape instead (`importTrack` of that one frame, then
// `setObstacleShape`): the person follows, held still between frames, and
// the latency is only shown.
//
// Dragging the person moves where every later frame is placed: the move of
// its reference point since the last frame is added to the frames' offset.
//
// Owns: the latest frame not yet given (one: a flood is thinned to the
// frame rate), the person's id, the offset, the recorder, the latency and
// rate figures, the sensing latency set on the world. Interface: `sim`,
// `messages`, `changed()` (the scene was edited) and `added(obstacle)` (a
// person to add when there is none).
import { errorText } from './dom.js';
import { TrackRecorder } from './keypoints.js';

/** Frames per second, and the latency's median, measured over this many frames. */
const RATE_WINDOW = 20;

/** Largest sensing latency the world takes (s; `World.setSensingLatency`). */
const MAX_LATENCY = 2;

export class HumanFeed {
  constructor(host) {
    this.host = host;
    this.pending = null;
    this.id = null;
    this.offset = [0, 0, 0];
    this.placed = null;
    this.lastT = -Infinity;
    this.recorder = new TrackRecorder();
    this.recording = false;
    this.arrivals = [];
    this.latencyMs = NaN;
    this.ages = [];
    this.sensingId = null;
    this.sensingLatency = NaN;
    this.thinned = 0;
    this.given = 0;
  }

  /** The person fed: `id` if it is a human of the scene, else none (the next frame picks one). */
  follow(id) {
    this.id = id;
    this.placed = null;
  }

  /**
   * Keeps `frame` (`{ layout, keypoints, confidence?, capturedAt }`,
   * keypoints relative to the person's placement, `capturedAt` in the
   * page's ms clock) as the one to give next; an older one not yet given is
   * dropped (counted in `thinned`).
   */
  offer(frame) {
    if (this.pending) this.thinned += 1;
    this.pending = frame;
    const now = performance.now();
    this.arrivals.push(now);
    if (this.arrivals.length > RATE_WINDOW) this.arrivals.shift();
  }

  /** Frames offered per second, over the last ones (0 before two). */
  get rate() {
    const a = this.arrivals;
    if (a.length < 2 || performance.now() - a[a.length - 1] > 2000) return 0;
    return (1000 * (a.length - 1)) / (a[a.length - 1] - a[0]);
  }

  /** The human obstacle to feed in `state`: the one followed, else the first human of the scene. */
  target(state) {
    const humans = (state.obstacles ?? []).filter((o) => o.shape?.type === 'human');
    const followed = humans.find((o) => o.id === this.id);
    if (followed) return followed;
    this.placed = null;
    this.id = humans[0]?.id ?? null;
    return humans[0] ?? null;
  }

  /**
   * Gives the pending frame to the world (called once per drawn frame,
   * before the steps). `place(anchor)` turns its keypoints into world
   * coordinates around `anchor` (the person's floor point). Returns true
   * when a frame was given.
   */
  apply(place, speed = 1) {
    const frame = this.pending;
    if (!frame) return false;
    this.pending = null;
    const { sim, messages } = this.host;
    // One read of the world's state per frame given (events not copied).
    const state = sim.world.state(sim.world.eventCount);
    const person = this.target(state);
    if (!person) {
      messages.status('No person in the scene to move: add a human (palette) for the frames to drive.');
      return false;
    }
    const id = person.id;
    const here = sim.wasm.referencePoint(person.shape);
    // The person was dragged since the last frame: later frames follow.
    if (this.placed) for (let i = 0; i < 3; i++) this.offset[i] += here[i] - this.placed[i];
    else this.offset = [0, 0, 0];
    const anchor = this.placed ? this.anchor : here;
    this.anchor = anchor;
    const keypoints = place(frame.keypoints, anchor).map((p) => [p[0] + this.offset[0], p[1] + this.offset[1], p[2] + this.offset[2]]);
    const now = performance.now();
    // The frame's time on the world's clock: now less its age, after the
    // last one (by a microsecond at least: a track's times increase).
    const worldT = state.t;
    const t = Math.max(this.lastT + 1e-6, worldT - (speed * (now - frame.capturedAt)) / 1000);
    // A world that takes frames on its clock gets none from its future
    // (paused: the frame waits for the clock to move).
    if (t > worldT && typeof sim.world.pushHumanFrame === 'function') {
      this.pending ??= frame;
      return false;
    }
    const out = { t, layout: frame.layout, keypoints, ...(frame.confidence ? { confidence: frame.confidence } : {}) };
    let shape;
    try {
      shape = pushFrame(sim, id, out);
    } catch (err) {
      messages.status(`A keypoint frame was refused: ${errorText(err)}`);
      return false;
    }
    this.lastT = t;
    this.measure(sim, id, now - frame.capturedAt, speed);
    this.given += 1;
    this.placed = sim.wasm.referencePoint(shape ?? sim.shapeOf(id));
    if (this.recording) this.recorder.add(out);
    sim.edited = true;
    return true;
  }

  /**
   * Takes one frame's end-to-end latency (`ageMs`, capture to the step,
   * page ms) into the figure shown and the person's sensing latency: the
   * median of the last frames', set on the world (`setSensingLatency`, on
   * its clock: `speed` × the page's) when it moves by a millisecond or
   * more, so that a frame is aged from when it was seen and its margins
   * grow only past that.
   */
  measure(sim, id, ageMs, speed) {
    this.ages.push(ageMs);
    if (this.ages.length > RATE_WINDOW) this.ages.shift();
    const sorted = [...this.ages].sort((a, b) => a - b);
    this.latencyMs = sorted[sorted.length >> 1];
    const latency = Math.min(MAX_LATENCY, (speed * this.latencyMs) / 1000);
    const world = sim.world;
    if (typeof world.setSensingLatency !== 'function' || !(latency >= 0)) return;
    if (this.sensingId === id && Math.abs(latency - this.sensingLatency) < 1e-3) return;
    try {
      world.setSensingLatency(id, latency);
    } catch (err) {
      this.host.messages.status(`The sensing latency was refused: ${errorText(err)}`);
      return;
    }
    this.sensingId = id;
    this.sensingLatency = latency;
  }

  /** Starts keeping the frames given (a new recording); `false` stops. */
  record(on) {
    if (on) this.recorder.clear();
    this.recording = on;
  }

  /** Forgets the person, the offset and the figures (a new scene). */
  reset() {
    this.pending = null;
    this.id = null;
    this.placed = null;
    this.offset = [0, 0, 0];
    this.lastT = -Infinity;
    this.arrivals = [];
    this.latencyMs = NaN;
    this.ages = [];
    this.sensingId = null;
    this.sensingLatency = NaN;
  }
}

/**
 * Gives `frame` to the world's person `id`: `pushHumanFrame` where the
 * library has it (returns null: the world poses the person), else the
 * frame's pose fitted as a one-frame track (returns the shape set).
 */
export function pushFrame(sim, id, frame) {
  const world = sim.world;
  if (typeof world.pushHumanFrame === 'function') {
    world.pushHumanFrame(id, frame);
    return null;
  }
  const track = { layout: frame.layout, frames: [{ t: 0, keypoints: frame.keypoints }] };
  const { shape } = sim.wasm.importTrack(JSON.stringify(track), {});
  world.setObstacleShape(id, shape);
  return shape;
}
