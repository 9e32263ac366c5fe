// A live person in Node: the camera's 2D keypoints lifted to metres by the
// person's height and placed facing the robot; frames from outside checked
// field by field; the `HumanFeed` giving the latest frame to a World (the
// person follows, a drag moves where later frames land, a flood is thinned
// to one frame per drawn frame); a recording that reads back as a keypoint
// track with exactly the frames given.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createRequire } from 'node:module';
import { GOOD_CONFIDENCE, LAYOUTS, MIN_SCORE, PROPORTIONS, TrackRecorder, calibrated, checkFrame, liftCoco17, metresPerPixel, placeInWorld } from '../../web/keypoints.js';
import { HumanFeed } from '../../web/human-feed.js';
import { cameraProblem } from '../../web/camera.js';
import { bridgeUrl } from '../../web/bridge-client.js';

const require = createRequire(import.meta.url);
const sa = require('../../crate/pkg-node/skeleton_avoidance.js');

/** A person standing square to the camera, 1.7 m, arms down, 400 px per metre; image y down. */
function standing2d(scale = 400, height = 1.7) {
  const P = PROPORTIONS;
  const px = (l, z) => [320 + l * scale, 900 - z * scale];
  const sh = P.hip * height + P.torso * height;
  const hw = P.shoulders * height / 2;
  const pts = [
    px(0, sh + P.nose * height), px(0.03, sh + 0.16), px(-0.03, sh + 0.16), px(0.07, sh + 0.14), px(-0.07, sh + 0.14),
    px(hw, sh), px(-hw, sh), px(hw, sh - P.upperArm * height), px(-hw, sh - P.upperArm * height),
    px(hw, sh - (P.upperArm + P.forearm) * height), px(-hw, sh - (P.upperArm + P.forearm) * height),
    px(0.085, P.hip * height), px(-0.085, P.hip * height), px(0.085, P.hip * height - P.thigh * height), px(-0.085, P.hip * height - P.thigh * height),
    px(0.085, P.ankle * height), px(-0.085, P.ankle * height),
  ];
  return { points: pts, scores: new Array(17).fill(0.9) };
}

test('2D keypoints become metres by the height; the unseen legs stand, a foreshortened arm leans forward', () => {
  const { points, scores } = standing2d();
  const s = metresPerPixel(points, scores, 1.7);
  assert.ok(Math.abs(s - 1 / 400) < 1e-12, `scale ${s}`);
  const body = liftCoco17(points, scores, 1.7);
  // Hips at the hip height, ankles at the ankle height, every point in the body's plane.
  assert.ok(Math.abs(body.keypoints[11][2] - PROPORTIONS.hip * 1.7) < 1e-9);
  assert.ok(Math.abs(body.keypoints[15][2] - PROPORTIONS.ankle * 1.7) < 1e-9);
  assert.ok(body.keypoints.every((p) => Math.abs(p[1]) < 1e-6 && p.every(Number.isFinite)));
  // The person's left (COCO's odd indices) is on the image's right: positive lateral.
  assert.ok(body.keypoints[5][0] > 0 && body.keypoints[6][0] < 0);
  // Legs out of the picture: put under the hips, standing.
  const upper = { points, scores: scores.map((c, k) => (k >= 13 ? 0.05 : c)) };
  const cut = liftCoco17(upper.points, upper.scores, 1.7);
  assert.ok(Math.abs(cut.keypoints[15][2] - PROPORTIONS.ankle * 1.7) < 1e-9);
  // Its low score is kept, on the library's scale: below the world's cut-off.
  assert.ok(Math.abs(cut.confidence[15] - (GOOD_CONFIDENCE * 0.05) / MIN_SCORE) < 1e-12, `${cut.confidence[15]}`);
  // A forearm seen at half its length leans forward by the rest.
  const reach = standing2d();
  reach.points[9] = [reach.points[7][0], reach.points[7][1] + (PROPORTIONS.forearm * 1.7 * 400) / 2];
  const leant = liftCoco17(reach.points, reach.scores, 1.7);
  const lean = leant.keypoints[9][1] - leant.keypoints[7][1];
  assert.ok(Math.abs(lean - Math.sqrt(0.75) * PROPORTIONS.forearm * 1.7) < 1e-9, `lean ${lean}`);
  // No shoulders seen: no person.
  assert.equal(liftCoco17(points, scores.map((c, k) => (k === 5 ? 0.1 : c)).map((c, k) => (k === 11 ? 0.1 : c)), 1.7, metresPerPixel(points, scores.map((c, k) => (k === 5 || k === 11 ? 0.1 : c)), 1.7)), null);
});

test('an estimator score is good for the world exactly when the page counts it as seen', () => {
  assert.equal(calibrated(0), 0);
  assert.equal(calibrated(1), 1);
  assert.equal(calibrated(MIN_SCORE), GOOD_CONFIDENCE);
  for (let s = 0; s <= 1.0001; s += 0.01) {
    assert.equal(calibrated(s) >= GOOD_CONFIDENCE, s >= MIN_SCORE, `score ${s}`);
    assert.ok(calibrated(s + 0.01) >= calibrated(s), 'monotone');
  }
  // A raised wrist MoveNet scores 0.46 (tests/data/camera/kinect-arm-up-down.mjpeg) is good.
  assert.ok(calibrated(0.46) >= GOOD_CONFIDENCE);
  assert.equal(calibrated(-1), 0);
  assert.equal(calibrated(2), 1);
});

test('placed in the world, the person faces the robot with their left on their left', () => {
  const body = [[0.2, 0, 1], [0, 0.3, 0]];
  const [left, forward] = placeInWorld(body, [1, 0, 0], [0, 0, 0]);
  // Facing -x: the person's left is -y.
  assert.deepEqual(left.map((v) => Math.round(v * 1e12) / 1e12), [1, -0.2, 1]);
  assert.deepEqual(forward.map((v) => Math.round(v * 1e12) / 1e12), [0.7, 0, 0]);
});

test('a frame from outside is checked field by field', () => {
  const ok = { t: 1, layout: 'coco17', keypoints: Array.from({ length: 17 }, () => [0, 0, 1]) };
  assert.deepEqual(checkFrame(ok), ok);
  const bad = [
    [null, /^frame:/],
    [{ ...ok, t: NaN }, /^t:/],
    [{ ...ok, t: '1' }, /^t:/],
    [{ ...ok, layout: 'coco18' }, /^layout:/],
    [{ ...ok, keypoints: ok.keypoints.slice(1) }, /^keypoints: coco17 has 17/],
    [{ ...ok, keypoints: Array.from({ length: 10_001 }, () => [0, 0, 0]) }, /^keypoints: more than 10000/],
    [{ ...ok, keypoints: ok.keypoints.map((p, k) => (k === 4 ? [0, Infinity, 0] : p)) }, /^keypoints\[4\]:/],
    [{ ...ok, confidence: [1] }, /^confidence:/],
    [{ ...ok, confidence: ok.keypoints.map((_, k) => (k === 2 ? 2 : 1)) }, /^confidence\[2\]:/],
    [{ ...ok, obstacle: 7 }, /^obstacle:/],
  ];
  for (const [value, message] of bad) assert.throws(() => checkFrame(value), { message });
  assert.deepEqual(Object.keys(LAYOUTS), ['coco17', 'body25', 'kinect32', 'blazepose33']);
});

function feedOn(world) {
  const statuses = [];
  const sim = { wasm: sa, world, edited: false, shapeOf: (id) => world.state().obstacles.find((o) => o.id === id)?.shape };
  const feed = new HumanFeed({ sim, messages: { status: (t) => statuses.push(t) } });
  return { feed, sim, statuses };
}

test('the feed gives the latest frame to the person, thins a flood, and follows a drag', () => {
  const world = new sa.World(sa.exampleScenario('human-reach'));
  try {
    const { feed, sim } = feedOn(world);
    feed.record(true);
    const { points, scores } = standing2d();
    const body = liftCoco17(points, scores, 1.7);
    const start = sa.referencePoint(sim.shapeOf('person'));
    // A flood: ten frames before one drawn frame; one is given.
    for (let i = 0; i < 10; i++) feed.offer({ layout: 'coco17', keypoints: body.keypoints, confidence: body.confidence, capturedAt: performance.now() });
    assert.equal(feed.thinned, 9);
    const place = (pts, anchor) => placeInWorld(pts, anchor);
    assert.equal(feed.apply(place), true);
    assert.equal(feed.apply(place), false, 'nothing pending: nothing given');
    assert.equal(feed.given, 1);
    const posed = sim.shapeOf('person');
    assert.equal(posed.type, 'human');
    const at = sa.referencePoint(posed);
    assert.ok(Math.hypot(at[0] - start[0], at[1] - start[1]) < 0.05, `placed where the person stood: ${at} vs ${start}`);
    assert.ok(Math.abs(posed.height - 1.7) < 0.1, `height ${posed.height}`);
    // The person is dragged 0.3 m along y: the next frame lands there too.
    world.setObstacleShape('person', sa.translateShape(posed, [0, 0.3, 0]));
    feed.offer({ layout: 'coco17', keypoints: body.keypoints, confidence: body.confidence, capturedAt: performance.now() });
    assert.equal(feed.apply(place), true);
    // The world poses a streamed person at its own clock (the frame's t
    // less the sensing latency), so the drag shows in the frames given:
    // every keypoint of the next frame lands 0.3 m further along y.
    const [before, after] = feed.recorder.frames;
    assert.equal(feed.recorder.frames.length, 2);
    after.keypoints.forEach((p, k) => {
      const q = before.keypoints[k];
      assert.ok(Math.abs(p[0] - q[0]) < 1e-9 && Math.abs(p[1] - q[1] - 0.3) < 1e-9 && Math.abs(p[2] - q[2]) < 1e-9, `keypoint ${k} followed the drag: ${p} vs ${q}`);
    });
    world.step(0.001);
  } finally {
    world.free();
  }
});

test('a recording reads back as a keypoint track with exactly the frames given', () => {
  const world = new sa.World(sa.exampleScenario('human-reach'));
  try {
    const { feed, sim } = feedOn(world);
    feed.record(true);
    const { points, scores } = standing2d();
    for (let i = 0; i < 5; i++) {
      const p = points.map(([x, y], k) => (k === 9 ? [x + 7 * i, y - 11.3 * i] : [x, y]));
      const body = liftCoco17(p, scores, 1.7);
      feed.offer({ layout: 'coco17', keypoints: body.keypoints, confidence: body.confidence, capturedAt: performance.now() });
      feed.apply((pts, anchor) => placeInWorld(pts, anchor));
      for (let k = 0; k < 33; k++) world.step(0.001);
    }
    feed.record(false);
    const text = feed.recorder.json();
    const track = JSON.parse(text);
    assert.equal(track.frames.length, 5, JSON.stringify(track.frames.map((f) => f.t)));
    assert.deepEqual(track.frames, feed.recorder.frames, 'every double round-trips through the JSON text');
    // The library reads it as a track (its fit may merge keyframes that pose alike).
    const { report } = sa.importTrack(text, {});
    assert.equal(report.layout, 'coco17');
    assert.ok(report.frames >= 1 && report.frames <= 5);
    assert.ok(sim.shapeOf('person'));
  } finally {
    world.free();
  }
  const r = new TrackRecorder(3);
  for (let t = 0; t < 5; t++) r.add({ t, layout: 'coco17', keypoints: [[t, 0, 0]] });
  r.add({ t: 4, layout: 'coco17', keypoints: [[9, 9, 9]] });
  assert.deepEqual(r.frames.map((f) => f.t), [2, 3, 4], 'bounded, times increasing');
});

test('a camera that is denied, absent or fails is said in words; a bridge only on this machine', () => {
  const named = (name, message = 'x') => Object.assign(new Error(message), { name });
  assert.match(cameraProblem(named('NotAllowedError')), /^The camera was denied\..*keeps running/);
  assert.match(cameraProblem(named('NotFoundError')), /^No camera was found/);
  assert.match(cameraProblem(named('OverconstrainedError')), /^No camera was found/);
  assert.match(cameraProblem(named('NotReadableError')), /in use by another program/);
  assert.equal(cameraProblem(new Error('the model could not be loaded')), 'The camera could not start: the model could not be loaded');
  assert.equal(bridgeUrl(' ws://127.0.0.1:8765/ '), 'ws://127.0.0.1:8765/');
  assert.equal(bridgeUrl('ws://localhost:9000'), 'ws://localhost:9000/');
  assert.throws(() => bridgeUrl('ws://192.168.1.2:8765/'), /^Error: bridge address: only a bridge on this machine/);
  assert.throws(() => bridgeUrl('wss://127.0.0.1:8765/'), /^Error: bridge address: expected ws:/);
  assert.throws(() => bridgeUrl('http://127.0.0.1:8765/'), /^Error: bridge address: expected ws:/);
  assert.throws(() => bridgeUrl('not a url'), /^Error: bridge address: not a URL/);
  assert.throws(() => bridgeUrl('ws://127.0.0.1.evil.example/'), /only a bridge on this machine/);
});
