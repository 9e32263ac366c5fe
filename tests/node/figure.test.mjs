// referencePoint and translateShape against crate/pkg-node: where each kind
// of figure is and how it moves, and the refusals naming the field.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const { referencePoint, translateShape, distance } = require('../../crate/pkg-node/skeleton_avoidance.js');

const near = (a, b, tol = 1e-12) => a.every((x, k) => Math.abs(x - b[k]) <= tol);

const FIGURES = [
  [{ type: 'point', p: [1, 2, 3] }, [1, 2, 3]],
  [{ type: 'segment', a: [0, 0, 0], b: [2, 0, 0] }, [1, 0, 0]],
  [{ type: 'sphere', center: [0.5, -0.5, 1], radius: 0.1 }, [0.5, -0.5, 1]],
  [{ type: 'capsule', a: [0, 0, 0], b: [0, 0, 1], radius: 0.1 }, [0, 0, 0.5]],
  [{ type: 'taperedCapsule', a: [0, 0, 0], b: [0, 2, 0], radius: [0.1, 0.2] }, [0, 1, 0]],
  [{ type: 'plane', normal: [0, 0, 2], offset: -1 }, [0, 0, 0.5]],
  [{ type: 'rectangle', center: [1, 1, 0], axes: [[1, 0, 0], [0, 1, 0]], halfExtents: [0.2, 0.1] }, [1, 1, 0]],
  [{ type: 'disk', center: [0, 1, 0], normal: [0, 0, 1], radius: 0.3 }, [0, 1, 0]],
  [{ type: 'polygon', vertices: [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]] }, [0.5, 0.5, 0]],
  [{ type: 'box', center: [0.2, 0.3, 0.4], halfExtents: [0.1, 0.1, 0.1] }, [0.2, 0.3, 0.4]],
  [{ type: 'human', position: [1, 0, 0], heading: 0, height: 1.75 }, [1, 0, 0]],
];

test('referencePoint: the centre, the middle, the vertex mean, the plane point nearest the origin, the floor point', () => {
  for (const [shape, expected] of FIGURES) {
    const p = referencePoint(shape);
    assert.ok(Array.isArray(p) && p.length === 3, JSON.stringify(p));
    assert.ok(near(p, expected), `${shape.type}: ${p} vs ${expected}`);
  }
});

test('translateShape moves the reference point by delta and keeps the form of the figure', () => {
  const delta = [0.25, -0.5, 0.125];
  for (const [shape, expected] of FIGURES) {
    const moved = translateShape(shape, delta);
    assert.equal(moved.type, shape.type);
    // A plane's reference point is its point nearest the origin: checked below.
    if (shape.type !== 'plane') assert.ok(near(referencePoint(moved), expected.map((x, k) => x + delta[k])), `${shape.type} moved`);
    for (const key of Object.keys(shape)) assert.ok(key in moved, `${shape.type}: keeps ${key}`);
    if (shape.type !== 'plane' && shape.type !== 'human') {
      // Distances to a far point change as a rigid translation implies.
      const far = { type: 'point', p: [5, 5, 5] };
      const before = distance(shape, { type: 'point', p: [5 - delta[0], 5 - delta[1], 5 - delta[2]] }).distance;
      assert.ok(Math.abs(distance(moved, far).distance - before) < 1e-9, `${shape.type} moved rigidly`);
    }
  }
  // A plane keeps its normal and shifts its offset: n·(x + δ) + offset' = 0.
  const plane = translateShape({ type: 'plane', normal: [0, 0, 1], offset: -1 }, [0, 0, 0.5]);
  assert.deepEqual(plane.normal, [0, 0, 1]);
  assert.ok(Math.abs(plane.offset + 1.5) < 1e-15);
});

test('bad figures and deltas throw an Error naming the field', () => {
  const ball = { type: 'sphere', center: [0, 0, 0], radius: 0.1 };
  const cases = [
    [() => referencePoint({ type: 'sphere', center: [0, 0, 0], radius: -1 }), /^shape\.radius: must be > 0$/],
    [() => referencePoint({ type: 'cone' }), /^shape\.type: unknown/],
    [() => referencePoint(null), /^shape: /],
    [() => referencePoint({ type: 'point', p: [0, NaN, 0] }), /^shape\.p\[1\]: not a finite number$/],
    [() => referencePoint({ type: 'human', position: [0, 0, 0], height: 0 }), /^shape\.height: must be > 0/],
    [() => translateShape(ball, [0, 0]), /^delta: expected \[x, y, z\], got 2 numbers$/],
    [() => translateShape(ball, 'up'), /^delta: /],
    [() => translateShape(ball, [0, Infinity, 0]), /^delta\[1\]: /],
    [() => translateShape(ball, [1e300, 0, 0]), /^delta\[0\]: /],
  ];
  for (const [f, re] of cases) assert.throws(f, (e) => e instanceof Error && re.test(e.message), String(f));
});

test('moveHumanHand moves only that arm; importTrack returns a human replaying a track, or refuses naming the field', () => {
  const { moveHumanHand, importTrack, World, exampleScenario } = require('../../crate/pkg-node/skeleton_avoidance.js');
  const person = { type: 'human', position: [1, 0.2, 0], heading: 3, animation: { clip: 'wave' } };
  const moved = moveHumanHand(person, 'right', [0.15, 0.05, 0.25]);
  assert.equal(moved.type, 'human');
  assert.equal(moved.animation, undefined);
  assert.ok(moved.pose.rightElbow > 0);
  assert.equal(moved.pose.leftElbow, undefined, 'the left arm keeps its angles');
  assert.throws(() => moveHumanHand(person, 'middle', [0, 0, 0]), /^Error: side: /);
  assert.throws(() => moveHumanHand({ type: 'sphere', center: [0, 0, 0], radius: 1 }, 'left', [0, 0, 0]), /^Error: shape: expected a human/);
  const fs = require('node:fs');
  const text = fs.readFileSync(new URL('../../web/tracks/reach-coco17.json', import.meta.url), 'utf8');
  const { shape, report } = importTrack(text);
  assert.equal(shape.type, 'human');
  assert.equal(report.frames, 75);
  assert.equal(shape.animation.keyframes.length, 75);
  // The imported figure is a valid obstacle; a refused track changes nothing.
  const w = new World(exampleScenario('human-reach'));
  w.setObstacleShape('person', shape);
  const before = JSON.stringify(w.state().obstacles);
  const bad = JSON.parse(text);
  bad.frames[5].t = bad.frames[4].t;
  assert.throws(() => importTrack(JSON.stringify(bad)), /frames\[5\]\.t: must increase/);
  assert.throws(() => importTrack(text, { layout: 'coco18' }), /^Error: layout: unknown layout/);
  assert.throws(() => importTrack('1,2,3', { format: 'csv', layout: 'coco17' }), /^Error: line 1: expected 52 cells/);
  assert.throws(() => importTrack(42), /^Error: text: expected a string/);
  assert.equal(JSON.stringify(w.state().obstacles), before);
  w.free();
});

test('importTrack reads BVH motion capture; malformed files are refused naming the field and change nothing', () => {
  const { importTrack, World, exampleScenario } = require('../../crate/pkg-node/skeleton_avoidance.js');
  const fs = require('node:fs');
  const text = fs.readFileSync(new URL('../../web/tracks/walk-by.bvh', import.meta.url), 'utf8');
  const { shape, report } = importTrack(text);
  assert.equal(report.layout, 'bvh');
  assert.equal(report.frames, 90);
  assert.ok(Math.abs(report.duration - 89 / 30) < 1e-9, String(report.duration));
  assert.equal(shape.animation.keyframes.length, 90);
  // Walking past along −y at 1.2 m/s: the last keyframe's root has moved
  // 3.56 m forward (the person faces −y), less the jitter filter's lag at
  // the end of a track (speed × smoothing, 3.6 cm), exact unfiltered.
  const last = shape.animation.keyframes[89];
  assert.ok(Math.abs(last.shift[0] - 1.2 * 89 / 30) < 0.05, JSON.stringify(last.shift));
  const raw = importTrack(text, { smoothing: 0 }).shape.animation.keyframes[89];
  assert.ok(Math.abs(raw.shift[0] - 1.2 * 89 / 30) < 1e-6, JSON.stringify(raw.shift));
  const w = new World(exampleScenario('human-reach'));
  w.setObstacleShape('person', shape);
  const before = JSON.stringify(w.state().obstacles);
  const cases = [
    [text.replace(/Frame Time: .*/, 'Frame Time: 0'), /^Frame Time: must be in \(0, 10\] s/],
    [text.replace('Frames: 90', 'Frames: 1000000000'), /^Frames: at most 100000 frames \(got 1000000000\)/],
    [text.slice(0, text.length - 2000), /^(Frames|line \d+): /],
    [text.replace('ROOT Hips', 'ROOT Torso'), /^ROOT: "Torso" is not a hips joint/],
    [text.replace(/\n(-?[0-9.]+) /, '\nNaN '), /^line \d+: value 1 \(Hips Xposition\): "NaN" is not a finite number/],
  ];
  for (const [bad, re] of cases) assert.throws(() => importTrack(bad), (e) => e instanceof Error && re.test(e.message), String(re));
  assert.throws(() => importTrack(text, { scale: -1 }), /^Error: scale: must be in \(0, 1000\]/);
  assert.throws(() => importTrack(text, { up: 'x' }), /^Error: up: expected "z" or "y"/);
  assert.equal(JSON.stringify(w.state().obstacles), before);
  w.free();
});

test('a human part seen with its own sigma gets its own margin; a bad partSigma is refused naming the field', () => {
  const { World, exampleScenario } = require('../../crate/pkg-node/skeleton_avoidance.js');
  const s = exampleScenario('human-reach');
  s.obstacles[0].shape.partSigma = { rightHand: 0.04 };
  s.sensing = { person: { sigma: 0.003 } };
  const w = new World(s);
  const u = w.state().uncertainty[0];
  const hand = 3 * Math.sqrt(0.003 ** 2 + 0.04 ** 2);
  assert.ok(Math.abs(u.partMargins.rightHand - hand) < 1e-12, JSON.stringify(u));
  assert.ok(Math.abs(u.partMargins.leftHand - 3 * 0.003) < 1e-12, JSON.stringify(u));
  assert.ok(Math.abs(u.radius - hand) < 1e-12);
  const before = JSON.stringify(w.state().obstacles);
  const bad = { ...s.obstacles[0].shape, partSigma: { rightHnd: 0.01 } };
  assert.throws(() => w.setObstacleShape('person', bad), /shape\.partSigma\.rightHnd: unknown part/);
  assert.throws(() => w.setObstacleShape('person', { ...bad, partSigma: { head: -1 } }), /shape\.partSigma\.head: must be in \[0, 1\] m/);
  assert.equal(JSON.stringify(w.state().obstacles), before);
  w.free();
});
