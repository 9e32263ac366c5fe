// World.pickSkeleton against crate/pkg-node: the skeleton's point under a
// ray as DH values, their round trip through controlPoint, misses, bad
// rays, prismatic and branched robots, and the point pinned.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const sa = require('../../crate/pkg-node/skeleton_avoidance.js');

/** Round trips agree to this (m). */
const EXACT = 1e-9;
const dist = (p, q) => Math.hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
const scene = (preset, q0, controller) => ({ robot: { preset }, q0, obstacles: [], dt: 0.001, duration: 1, ...(controller ? { controller } : {}) });

/** A ray perpendicular to segment `k` through the point at fraction `t` of it, from 2 m away. */
function rayAt(state, k, t, side = 0) {
  const s = state.skeleton.segments[k];
  const a = state.skeleton.nodes[s.from];
  const b = state.skeleton.nodes[s.to];
  const v = [0, 1, 2].map((i) => b[i] - a[i]);
  const target = [0, 1, 2].map((i) => a[i] + t * v[i]);
  // A unit vector perpendicular to v: v × (an axis far from v), turned by `side`.
  const axis = Math.abs(v[2]) < 0.9 * Math.hypot(...v) ? [0, 0, 1] : [1, 0, 0];
  let n = [v[1] * axis[2] - v[2] * axis[1], v[2] * axis[0] - v[0] * axis[2], v[0] * axis[1] - v[1] * axis[0]];
  if (side) n = n.map((x) => -x);
  const l = Math.hypot(...n);
  n = n.map((x) => x / l);
  return { origin: target.map((x, i) => x + 2 * n[i]), direction: n.map((x) => -x), target };
}

test('pickSkeleton gives DH values whose control point is the picked point, on every preset', () => {
  for (const preset of sa.presetNames()) {
    const spec = sa.robotPreset(preset);
    const dof = spec.joints.length + (spec.branches ?? []).reduce((n, b) => n + b.joints.length, 0);
    const q = Array.from({ length: dof }, (_, k) => (k % 2 ? -0.5 : 0.35));
    const w = new sa.World(scene(preset, q));
    const state = w.state();
    let exact = 0;
    state.skeleton.segments.forEach((seg, k) => {
      for (const side of [0, 1]) {
        const { origin, direction, target } = rayAt(state, k, 0.5, side);
        const pick = w.pickSkeleton(origin, direction);
        assert.ok(pick, `${preset} segment ${k}: missed`);
        for (const key of ['link', 'd', 'a', 'segment', 'position', 'distance', 'offset', 'radius']) assert.ok(key in pick, key);
        // DH values → position through the public controlPoint: the same point.
        const cp = sa.controlPoint(spec, state.q, { link: pick.link, d: pick.d, a: pick.a });
        assert.ok(dist(cp.position, pick.position) < EXACT, `${preset} ${k}: ${JSON.stringify(pick)}`);
        assert.ok(pick.offset <= pick.radius + 0.02 + EXACT);
        if (pick.segment === k && dist(pick.position, target) < EXACT) exact += 1;
      }
    });
    assert.ok(exact >= state.skeleton.segments.length, `${preset}: ${exact} exact picks for ${state.skeleton.segments.length} segments`);
    w.free();
  }
});

test('pickSkeleton on a branch and on a prismatic slide', () => {
  // dual-arm: a torso row, then the rows of each arm (a branch).
  const w = new sa.World(sa.exampleScenario('dual-arm-self'));
  const state = w.state();
  const torso = sa.robotPreset('dual-arm').joints.length;
  const onBranch = state.skeleton.segments.map((s, i) => [s.link, i]).filter(([l]) => l > torso);
  assert.ok(onBranch.length > 0);
  for (const [link, seg] of onBranch) {
    const { origin, direction, target } = rayAt(state, seg, 0.5);
    const pick = w.pickSkeleton(origin, direction);
    if (pick.segment !== seg) continue;
    assert.equal(pick.link, link);
    assert.ok(dist(pick.position, target) < EXACT);
  }
  w.free();

  // stanford: the slide (row 3) at 0.8 m; a point 3/4 along it has d' = 0.6.
  const s = new sa.World(scene('stanford', [0.3, 0.5, 0.8, 0, 0, 0]));
  const st = s.state();
  const slide = st.skeleton.segments.findIndex((x) => x.link === 3);
  const ray = rayAt(st, slide, 0.75);
  const p = s.pickSkeleton(ray.origin, ray.direction);
  assert.equal(p.link, 3);
  assert.ok(Math.abs(p.d - 0.6) < EXACT && Math.abs(p.a) < EXACT, JSON.stringify(p));
  // Pinned there, though the slide's minimum (0.3 m) is shorter than d'.
  s.setController({ selection: 'pinned', pinned: [{ link: 3, d: p.d, a: p.a }] });
  s.step(0.001);
  const cp = s.state().controlPoints[0];
  assert.equal(cp.link, 3);
  assert.ok(Math.abs(cp.d - p.d) < EXACT && dist(cp.position, p.position) < 1e-3);
  s.free();
});

test('pickSkeleton: null for a ray that misses, an Error naming the field for a bad ray', () => {
  const w = new sa.World(scene('planar3', [0, 0, 0]));
  const before = JSON.stringify(w.state());
  const pick = w.pickSkeleton([0.55, 0.01, 1], [0, 0, -1]);
  assert.equal(pick.link, 2);
  assert.ok(Math.abs(pick.a - 0.15) < EXACT && Math.abs(pick.d) < EXACT);
  assert.ok(Math.abs(pick.distance - 1) < EXACT && Math.abs(pick.offset - 0.01) < EXACT);
  assert.equal(w.pickSkeleton([0.55, 0, 1], [0, 0, 1]), null);
  assert.equal(w.pickSkeleton([0.55, 1, 1], [0, 0, -1]), null);
  assert.throws(() => w.pickSkeleton([0, 0, 0], [0, 0, 0]), { message: 'direction: must not be zero' });
  assert.throws(() => w.pickSkeleton([0, NaN, 0], [0, 0, 1]), /^Error: origin\[1\]|origin\[1\]/);
  assert.throws(() => w.pickSkeleton([0, 0], [0, 0, 1]), /origin: expected \[x, y, z\]/);
  assert.throws(() => w.pickSkeleton('x', [0, 0, 1]), /origin/);
  assert.throws(() => w.pickSkeleton([0, 0, 1]), /direction/);
  assert.equal(JSON.stringify(w.state()), before);
  w.free();
  assert.throws(() => w.pickSkeleton([0, 0, 1], [0, 0, -1]), /freed/);
});
