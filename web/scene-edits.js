// The scene's edits and its ways out of the page, as methods mixed into the
// Playground: obstacles added, moved, resized, deleted, selected; the scene
// as a scenario (Save, Share, a shared link, a file).
import { clone, errorText, h } from './dom.js';
import { decodeShare, encodeShare, readScenarioFile } from './scenario-io.js';
import { add, defaultShape, importTrack, isPoint, len, mul, sub, translateShape } from './shapes.js';

export const sceneMethods = {
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
  },

  async loadFile(file) {
    if (!file) return;
    try {
      const scenario = await readScenarioFile(file);
      this.loadScenario(scenario, `file "${file.name}"`);
    } catch (err) {
      this.showError(`${errorText(err)}\nThe current scene is unchanged.`);
    } finally {
      if (this.panel) this.panel.file.value = '';
    }
  },

  /** A URL that restores the current scene exactly. */
  shareUrl() {
    const url = new URL(location.href);
    url.hash = encodeShare(this.currentScenario());
    return url.href;
  },

  /**
   * Copies a link to the scene as it is now and shows it in the panel. The
   * address bar is left alone, so a reload never brings back a stale scene.
   */
  share() {
    const url = this.shareUrl();
    const show = (said) => {
      if (!this.panel) return;
      const field = h('input', { type: 'text', readonly: true, value: url, id: 'share-link', 'aria-label': 'link to this scene', onfocus: (e) => e.target.select() });
      this.panel.status.replaceChildren(said, field);
    };
    show('Link to this scene:');
    navigator.clipboard?.writeText(url).then(() => show('Link copied:'), () => {});
    return url;
  },

  /** Drops a `#scenario=` the scene no longer matches from the address bar. */
  forgetShareLink() {
    if (!this.fromShareLink || !location.hash.startsWith('#scenario=')) return;
    this.fromShareLink = false;
    history.replaceState(null, '', location.pathname + location.search);
    this.lastHash = '';
  },

  /** Loads the scenario carried by a URL fragment; returns false when there is none. */
  loadHash(hash) {
    let scenario;
    try {
      scenario = decodeShare(hash);
    } catch (err) {
      this.showError(`${errorText(err)}\nThe current scene is unchanged.`);
      return true;
    }
    if (!scenario) return false;
    this.fromShareLink = !this.loadScenario(scenario, 'shared scenario') && Boolean(this.options.share);
    return true;
  },

  nextId(type) {
    const ids = new Set((this.scenario.obstacles ?? []).map((o) => o.id));
    for (let k = 1; ; k++) if (!ids.has(`${type}-${k}`)) return `${type}-${k}`;
  },

  /** Adds an obstacle of `type` in front of the arm; returns its id (or null). */
  addObstacle(type) {
    const nodes = this.state.skeleton.nodes;
    const base = nodes[0];
    const reach = Math.max(0.2, ...nodes.map((n) => len(sub(n, base))));
    const planar = nodes.every((n) => Math.abs(n[2] - base[2]) < 1e-9);
    const k = (this.scenario.obstacles ?? []).length;
    const id = this.nextId(type);
    const spec = { id, shape: this.freeShape(type, base, reach, planar, k) };
    const ok = this.guard(() => { this.world.addObstacle(spec); return true; });
    if (!ok) return null;
    this.edited = true;
    this.scenario.obstacles = [...(this.scenario.obstacles ?? []), spec];
    this.forgetShareLink();
    this.select(id);
    this.setStatus(`Added ${id}.`);
    return id;
  },

  /**
   * A new obstacle's figure where it does not touch the arm: candidate
   * centres around the base, the first whose clearance from the arm (asked
   * of the library) is at least a tenth of the reach; the farthest one if
   * none is.
   */
  freeShape(type, base, reach, planar, k) {
    let best = null;
    for (let i = 0; i < 24; i++) {
      const angle = (k * 0.9 + i * 0.7) % (2 * Math.PI);
      const r = (0.55 + 0.05 * (i % 4)) * reach;
      const c = add(base, [r * Math.cos(angle), r * Math.sin(angle), planar ? 0 : (0.3 + 0.1 * (i % 3)) * reach]);
      const shape = defaultShape(type, c, reach);
      let clearance = -Infinity;
      try { clearance = this.world.clearanceTo ? this.world.clearanceTo(shape) : Infinity; } catch { /* keep looking */ }
      if (clearance >= 0.1 * reach) return shape;
      if (!best || clearance > best.clearance) best = { shape, clearance };
    }
    return best.shape;
  },

  removeSelected() {
    const id = this.selected;
    if (!id) return;
    if (!this.guard(() => { this.world.removeObstacle(id); return true; })) return;
    this.edited = true;
    this.scenario.obstacles = this.scenario.obstacles.filter((o) => o.id !== id);
    this.forgetShareLink();
    this.select(null);
    this.setStatus(`Deleted ${id}.`);
  },

  /**
   * Replays a recorded keypoint track (a `File`: JSON, CSV or BVH) with the
   * selected human (or a new one when no human is selected). A track the
   * library refuses leaves the scene as it was, and says why.
   */
  async openTrack(file) {
    if (!file) return;
    try {
      const text = await file.text();
      const csv = /\.csv$/i.test(file.name);
      const bvh = /\.bvh$/i.test(file.name);
      const options = csv ? { format: 'csv', layout: /body25/i.test(file.name) ? 'body25' : /kinect/i.test(file.name) ? 'kinect32' : 'coco17' }
        : bvh ? { format: 'bvh' } : {};
      const { shape, report } = importTrack(text, options);
      const id = this.selected && this.shapeOf(this.selected)?.type === 'human' ? this.selected : null;
      if (id) {
        if (!this.setShape(id, shape)) return;
      } else {
        const spec = { id: this.nextId('human'), shape };
        if (!this.guard(() => { this.world.addObstacle(spec); return true; })) return;
        this.edited = true;
        this.scenario.obstacles = [...(this.scenario.obstacles ?? []), spec];
        this.forgetShareLink();
        this.select(spec.id);
      }
      this.refreshSelected();
      this.setStatus(`Track "${file.name}": ${report.layout}, ${report.frames} frames over ${report.duration.toFixed(2)} s, height ${report.height.toFixed(2)} m; ${report.filled} keypoints filled, ${report.clamped} angles clamped.`);
    } catch (err) {
      this.showError(`${errorText(err)}\nThe current scene is unchanged.`);
    }
  },

  shapeOf(id) {
    return this.world.state(this.world.eventCount).obstacles.find((o) => o.id === id)?.shape;
  },

  /** Replaces the shape of obstacle `id`; returns false (message shown) on error. */
  setShape(id, shape) {
    const ok = this.guard(() => { this.world.setObstacleShape(id, shape); return true; });
    if (!ok) return false;
    this.edited = true;
    this.scenario.obstacles = this.scenario.obstacles.map((o) => (o.id === id ? { ...o, shape: clone(shape) } : o));
    this.forgetShareLink();
    return true;
  },

  editSelected(f) {
    if (!this.selected) return;
    const shape = this.shapeOf(this.selected);
    // An edit the library refuses (a figure out of range) leaves it as it was.
    const edited = shape && this.guard(() => f(shape));
    if (edited && this.setShape(this.selected, edited)) this.refreshSelected();
  },

  select(id) {
    this.selected = id;
    this.viewer.setSelected(id);
    this.refreshObstacleList();
    this.refreshSelected();
  },
};
