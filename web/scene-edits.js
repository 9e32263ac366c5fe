// The scene's obstacles as the person edits them: added in front of the arm,
// moved, resized, rotated, deleted, selected, a human given a recorded track.
//
// Owns: the selection (`selected`). Interface, given by the Playground:
// `sim` (the world and the scenario, where each edit is recorded),
// `viewer()` (to show the selection), `messages`, `changed()` (the scene no
// longer matches a shared link) and `shown(list)` (the panel shows the
// selected obstacle again, and the list of obstacles too when `list`).
import { clone, errorText } from './dom.js';
import { add, defaultShape, importTrack, len, sub } from './shapes.js';

export class SceneEdits {
  /**
   * @param {{ sim: import('./sim.js').Sim, viewer: () => any, messages: import('./messages.js').Messages,
   *           changed: () => void, shown: (list: boolean) => void }} host
   */
  constructor(host) {
    this.host = host;
    this.selected = null;
  }

  /** Forgets the selection (a new scene). */
  clear() {
    this.selected = null;
    this.host.viewer().setSelected(null);
  }

  /** Adds an obstacle of `type` in front of the arm; returns its id (or null). */
  addObstacle(type) {
    const { sim, messages } = this.host;
    const nodes = sim.state.skeleton.nodes;
    const base = nodes[0];
    const reach = Math.max(0.2, ...nodes.map((n) => len(sub(n, base))));
    const planar = nodes.every((n) => Math.abs(n[2] - base[2]) < 1e-9);
    const k = (sim.scenario.obstacles ?? []).length;
    const id = sim.nextId(type);
    const spec = { id, shape: this.freeShape(type, { base, reach, planar, k }) };
    if (!this.added(spec)) return null;
    messages.status(`Added ${id}.`);
    return id;
  }

  /** Adds `spec` to the world and the scenario and selects it; false (message shown) when refused. */
  added(spec) {
    const { sim, messages } = this.host;
    if (!messages.guard(() => { sim.world.addObstacle(spec); return true; })) return false;
    sim.recordObstacles((list) => [...list, spec]);
    this.host.changed();
    this.select(spec.id);
    return true;
  }

  /**
   * A new obstacle's figure where it does not touch the arm: candidate
   * centres around the base, the first whose clearance from the arm (asked
   * of the library) is at least a tenth of the reach; the farthest one if
   * none is.
   */
  freeShape(type, { base, reach, planar, k }) {
    const world = this.host.sim.world;
    let best = null;
    for (let i = 0; i < 24; i++) {
      const angle = (k * 0.9 + i * 0.7) % (2 * Math.PI);
      const r = (0.55 + 0.05 * (i % 4)) * reach;
      const c = add(base, [r * Math.cos(angle), r * Math.sin(angle), planar ? 0 : (0.3 + 0.1 * (i % 3)) * reach]);
      const shape = defaultShape(type, c, reach);
      let clearance = -Infinity;
      try { clearance = world.clearanceTo ? world.clearanceTo(shape) : Infinity; } catch { /* keep looking */ }
      if (clearance >= 0.1 * reach) return shape;
      if (!best || clearance > best.clearance) best = { shape, clearance };
    }
    return best.shape;
  }

  removeSelected() {
    const { sim, messages } = this.host;
    const id = this.selected;
    if (!id) return;
    if (!messages.guard(() => { sim.world.removeObstacle(id); return true; })) return;
    sim.recordObstacles((list) => list.filter((o) => o.id !== id));
    this.host.changed();
    this.select(null);
    messages.status(`Deleted ${id}.`);
  }

  /**
   * Replays a recorded keypoint track (a `File`: JSON, CSV or BVH) with the
   * selected human (or a new one when no human is selected). A track the
   * library refuses leaves the scene as it was, and says why.
   */
  async openTrack(file) {
    if (!file) return;
    const { sim, messages } = this.host;
    try {
      const text = await file.text();
      const csv = /\.csv$/i.test(file.name);
      const bvh = /\.bvh$/i.test(file.name);
      const options = csv ? { format: 'csv', layout: /body25/i.test(file.name) ? 'body25' : /kinect/i.test(file.name) ? 'kinect32' : /blazepose|mediapipe/i.test(file.name) ? 'blazepose33' : 'coco17' }
        : bvh ? { format: 'bvh' } : {};
      const { shape, report } = importTrack(text, options);
      const id = this.selected && sim.shapeOf(this.selected)?.type === 'human' ? this.selected : null;
      if (id ? !this.setShape(id, shape) : !this.added({ id: sim.nextId('human'), shape })) return;
      this.host.shown(false);
      messages.status(`Track "${file.name}": ${report.layout}, ${report.frames} frames over ${report.duration.toFixed(2)} s, height ${report.height.toFixed(2)} m; ${report.filled} keypoints filled, ${report.clamped} angles clamped.`);
    } catch (err) {
      messages.error(`${errorText(err)}\nThe current scene is unchanged.`);
    }
  }

  /** Replaces the shape of obstacle `id`; returns false (message shown) on error. */
  setShape(id, shape) {
    const { sim, messages } = this.host;
    if (!messages.guard(() => { sim.world.setObstacleShape(id, shape); return true; })) return false;
    sim.recordObstacles((list) => list.map((o) => (o.id === id ? { ...o, shape: clone(shape) } : o)));
    this.host.changed();
    return true;
  }

  /** Applies `f` to the selected obstacle's shape; a refused edit leaves it as it was. */
  editSelected(f) {
    if (!this.selected) return;
    const shape = this.host.sim.shapeOf(this.selected);
    const edited = shape && this.host.messages.guard(() => f(shape));
    if (edited && this.setShape(this.selected, edited)) this.host.shown(false);
  }

  select(id) {
    this.selected = id;
    this.host.viewer().setSelected(id);
    this.host.shown(true);
  }
}
