// The simulated scene the widget shows: the library's `World`, the scenario
// as loaded and edited since, the robot's spec, and the state read from the
// world at the last change.
//
// Owns: the wasm module, the world, the scenario, the robot spec, the last
// state read, whether the picture must be drawn again (`edited`) and how
// many of the world's events were shown (`seenEvents`). No interface: it
// knows nothing of the page. The Playground replaces the world; the parts
// read it and record their edits here.
import { clone } from './dom.js';
import { isPoint, mul, translateShape } from './shapes.js';

export class Sim {
  constructor() {
    this.wasm = null;
    this.world = null;
    this.scenario = null;
    this.robotSpec = null;
    this.state = null;
    this.edited = false;
    this.seenEvents = 0;
  }

  /** The robot spec a scenario's `robot` names (a preset, `{ preset }` or a spec). */
  robotSpecOf(robot) {
    if (typeof robot === 'string') return this.wasm.robotPreset(robot);
    if (robot && typeof robot === 'object' && 'preset' in robot) return this.wasm.robotPreset(robot.preset);
    return robot;
  }

  /** Takes `world` (the old one is freed) with the scenario it was made from. */
  replace(world, scenario, robotSpec = this.robotSpec) {
    this.world?.free();
    this.world = world;
    this.scenario = clone(scenario);
    this.robotSpec = robotSpec;
    this.seenEvents = 0;
    this.state = world.state();
    this.edited = true;
  }

  free() {
    this.world?.free();
    this.world = null;
  }

  /** The influence distance in force (m): the scenario's or the library's default. */
  influence() {
    return this.world?.controller().influenceDistance ?? this.scenario.controller?.influenceDistance ?? 0.3;
  }

  /** The controller fields of `partial` recorded in the scenario (the world has them already). */
  recordController(partial) {
    this.scenario.controller = { ...(this.scenario.controller ?? {}), ...partial };
  }

  /** The obstacles of the scenario after `change(list)`; the picture is drawn again. */
  recordObstacles(change) {
    this.scenario.obstacles = change(this.scenario.obstacles ?? []);
    this.edited = true;
  }

  /** The shape of obstacle `id` as it is now. */
  shapeOf(id) {
    return this.world.state(this.world.eventCount).obstacles.find((o) => o.id === id)?.shape;
  }

  /** An obstacle id of `type` not in use (`sphere-3`). */
  nextId(type) {
    const ids = new Set((this.scenario.obstacles ?? []).map((o) => o.id));
    for (let k = 1; ; k++) if (!ids.has(`${type}-${k}`)) return `${type}-${k}`;
  }

  /**
   * The scene as a scenario. By default it is the scene as it is now: the
   * current joints become `q0` and every obstacle is where it is now (a
   * moving one continues its motion from there). With `asEdited`, `q0` and
   * the moving obstacles are those of the scenario as loaded and edited.
   */
  currentScenario({ keepQ0 = false, asEdited = keepQ0 } = {}) {
    const s = clone(this.scenario);
    const state = this.world.state();
    const shapes = new Map(state.obstacles.map((o) => [o.id, o.shape]));
    s.obstacles = (s.obstacles ?? []).map((o) => {
      const moving = o.motion && o.motion.type !== 'static';
      if (!shapes.has(o.id) || (moving && asEdited)) return o;
      let shape = clone(shapes.get(o.id));
      // A waypoint motion starts at its first point: start it from here.
      if (moving && o.motion.type === 'waypoints' && isPoint(o.motion.points?.[0])) shape = translateShape(shape, mul(o.motion.points[0], -1));
      return { ...o, shape };
    });
    if (!keepQ0) s.q0 = Array.from(state.q);
    return s;
  }
}
