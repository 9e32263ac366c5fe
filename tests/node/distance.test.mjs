// The JS contract of `distance(a, b)` (DESIGN.md), against the Node build
// at crate/pkg-node.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const { distance } = require('../../crate/pkg-node/skeleton_avoidance.js');

const close = (a, b, tol = 1e-12) => Math.abs(a - b) <= tol;
const closeVec = (a, b, tol = 1e-12) => a.length === 3 && a.every((x, i) => close(x, b[i], tol));

const figures = {
  point: { type: 'point', p: [3, 0, 0] },
  segment: { type: 'segment', a: [3, -1, 0], b: [3, 1, 0] },
  sphere: { type: 'sphere', center: [3, 0, 0], radius: 0.5 },
  capsule: { type: 'capsule', a: [3, -1, 0], b: [3, 1, 0], radius: 0.5 },
  taperedCapsule: { type: 'taperedCapsule', a: [3, 0, -1], b: [3, 0, 1], radius: [0.5, 0.2] },
  plane: { type: 'plane', normal: [2, 0, 0], offset: -6 },
  rectangle: { type: 'rectangle', center: [3, 0, 0], axes: [[0, 1, 0], [0, 0, 1]], halfExtents: [1, 1] },
  disk: { type: 'disk', center: [3, 0, 0], normal: [1, 0, 0], radius: 1 },
  polygon: { type: 'polygon', vertices: [[3, -1, -1], [3, 1, -1], [3, 1, 1], [3, -1, 1]] },
  box: { type: 'box', center: [3.5, 0, 0], halfExtents: [0.5, 1, 1], rotation: [0, 0, 0, 1] },
  convexHull: {
    type: 'convexHull',
    points: [[3, -1, -1], [3, 1, -1], [3, 1, 1], [3, -1, 1], [4, 0, 0]],
  },
};
// Distance from the unit sphere at the origin to each figure (all lie at
// x ≥ 3 with their nearest part at x = 3, minus their own radius on the axis).
const expected = {
  point: 2, segment: 2, sphere: 1.5, capsule: 1.5, taperedCapsule: null,
  plane: 2, rectangle: 2, disk: 2, polygon: 2, box: 2, convexHull: 2,
};

test('distance returns { distance, pointA, pointB } for every figure, either order', () => {
  const unit = { type: 'sphere', center: [0, 0, 0], radius: 1 };
  for (const [name, fig] of Object.entries(figures)) {
    const d = distance(unit, fig);
    assert.equal(typeof d.distance, 'number', name);
    assert.ok(Array.isArray(d.pointA) && Array.isArray(d.pointB), name);
    assert.equal(typeof d.unique, 'boolean', name);
    if (name !== 'taperedCapsule') {
      assert.ok(close(d.distance, expected[name], 1e-6), `${name}: ${d.distance}`);
    }
    const r = distance(fig, unit);
    assert.ok(close(r.distance, d.distance, 1e-9), `${name} reversed`);
    assert.ok(closeVec(r.pointA, d.pointB, 1e-6), `${name} reversed witness`);
  }
});

test('a sphere to a point', () => {
  const d = distance({ type: 'sphere', center: [0, 0, 0], radius: 1 }, { type: 'point', p: [3, 0, 0] });
  assert.ok(close(d.distance, 2));
  assert.deepEqual(d.pointA, [1, 0, 0]);
  assert.deepEqual(d.pointB, [3, 0, 0]);
  assert.equal(d.unique, true);
});

test('overlapping solids are negative by the depth, touching figures 0', () => {
  const s1 = { type: 'sphere', center: [0, 0, 0], radius: 1 };
  const s2 = { type: 'sphere', center: [1.5, 0, 0], radius: 1 };
  assert.ok(close(distance(s1, s2).distance, -0.5));
  const a = { type: 'segment', a: [-1, 0, 0], b: [1, 0, 0] };
  const b = { type: 'segment', a: [0, -1, 0], b: [0, 1, 0] };
  assert.equal(distance(a, b).distance, 0);
});

test('parallel segments: the middle of the overlap, not unique', () => {
  const d = distance(
    { type: 'segment', a: [0, 0, 0], b: [2, 0, 0] },
    { type: 'segment', a: [1, 1, 0], b: [4, 1, 0] },
  );
  assert.ok(close(d.distance, 1));
  assert.ok(closeVec(d.pointA, [1.5, 0, 0]));
  assert.equal(d.unique, false);
});

test('a plane is normalised with its offset', () => {
  const d = distance({ type: 'plane', normal: [0, 0, 2], offset: -2 }, { type: 'point', p: [0, 0, 3] });
  assert.ok(close(d.distance, 2));
  assert.ok(closeVec(d.pointA, [0, 0, 1]));
});

test('bad input throws an Error naming the field and the reason', () => {
  const p = { type: 'point', p: [0, 0, 0] };
  const cases = [
    [p, { type: 'sphere', center: [0, 0, 0], radius: 0 }, /^b\.radius: must be > 0$/],
    [p, { type: 'sphere', center: [0, 0, 0], radius: -2 }, /^b\.radius: must be > 0$/],
    [{ type: 'cone' }, p, /^a\.type: unknown primitive "cone" \(known: point, /],
    [{ p: [0, 0, 0] }, p, /^a\.type: /],
    [null, p, /^a: /],
    [42, p, /^a: /],
    [{ type: 'point', p: [0, NaN, 0] }, p, /^a\.p\[1\]: not a finite number$/],
    [{ type: 'point', p: [0, Infinity, 0] }, p, /^a\.p\[1\]: not a finite number$/],
    [{ type: 'point', p: [0, 'x', 0] }, p, /^a\.p\[1\]: /],
    [{ type: 'point', p: [0, 0] }, p, /^a\.p: /],
    [{ type: 'point', p: [0, 0, 0, 5] }, p, /^a\.p: too many elements: got 4, more than this field holds$/],
    [{ type: 'sphere', center: [0, 0, 0] }, p, /^a: missing `radius` \(a sphere needs center, radius\)$/],
    [{ type: 'point', p: [0, 0, 0], radius: 1 }, p, /^a: `radius` is not a field of a point/],
    [{ type: 'point', p: [0, 0, 0], colour: 1 }, p, /^a\.colour: unknown field "colour"/],
    [{ type: 'taperedCapsule', a: [0, 0, 0], b: [1, 0, 0], radius: [0.1, NaN] }, p, /^a\.radius\[1\]: not a finite number$/],
    [{ type: 'point', p: [0, 'x', 0] }, p, /^a\.p\[1\]: expected a number, got the string "x"$/],
    [{ type: 'polygon', vertices: 'x' }, p, /^a\.vertices: /],
    [p, { type: 'plane', normal: [0, 0, 0], offset: 1 }, /^b\.normal: must not be zero$/],
    [p, { type: 'disk', center: [0, 0, 0], normal: [0, 0, 0], radius: 1 }, /^b\.normal: must not be zero$/],
    [p, { type: 'disk', center: [0, 0, 0], normal: [0, 0, 1], radius: 0 }, /^b\.radius: must be > 0$/],
    [
      p,
      { type: 'rectangle', center: [0, 0, 0], axes: [[1, 0, 0], [2, 0, 0]], halfExtents: [1, 1] },
      /^b\.axes: must be orthogonal$/,
    ],
    [
      p,
      { type: 'rectangle', center: [0, 0, 0], axes: [[1, 0, 0], [0, 1, 0]], halfExtents: [0, 1] },
      /^b\.halfExtents\[0\]: must be > 0$/,
    ],
    [{ type: 'polygon', vertices: [[0, 0, 0], [1, 0, 0]] }, p, /^a\.vertices: polygon needs at least 3 vertices$/],
    [
      { type: 'polygon', vertices: [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 1]] },
      p,
      /^a\.vertices: polygon is not planar$/,
    ],
    [
      { type: 'polygon', vertices: [[0, 0, 0], [2, 2, 0], [2, 0, 0], [0, 1, 0]] },
      p,
      /^a\.vertices: polygon is self-intersecting$/,
    ],
    [p, { type: 'box', center: [0, 0, 0], halfExtents: [1, 1, 1], rotation: [0, 0, 0, 0] }, /^b\.rotation: must not be zero$/],
    [p, { type: 'convexHull', points: [[0, 0, 0], [1, 0, 0], [0, 1, 0]] }, /^b\.points: needs at least 4 points$/],
  ];
  for (const [a, b, re] of cases) {
    assert.throws(() => distance(a, b), (e) => e instanceof Error && re.test(e.message), JSON.stringify([a, b]));
  }
});

test('nothing traps, whatever is passed', () => {
  const junk = [undefined, null, true, 0, 'sphere', [], {}, { type: 'box' }, { type: 'polygon', vertices: 'x' },
    { type: 'segment', a: [1e308, 1e308, 1e308], b: [-1e308, -1e308, -1e308] }];
  for (const a of junk) {
    for (const b of junk) {
      try {
        distance(a, b);
      } catch (e) {
        assert.ok(e instanceof Error, `${String(e)}`);
      }
    }
  }
  // Still alive afterwards.
  assert.ok(close(distance({ type: 'point', p: [0, 0, 0] }, { type: 'point', p: [0, 3, 4] }).distance, 5));
});
