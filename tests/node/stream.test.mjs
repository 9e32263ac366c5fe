// A person from a sensor (World.pushHumanFrame) against crate/pkg-node: a
// recording streamed frame by frame moves the arm exactly as the same
// recording imported as a track with the same latency; bad frames are
// refused naming the field, the world unchanged; a dropout grows the hand's
// margin at 2.0 m/s while the arm keeps clear of the grown region.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const sa = require('../../crate/pkg-node/skeleton_avoidance.js');

const CSV = new URL('../../crate/tests/data/recordings/kinect2-Ges04_comehere.csv', import.meta.url);

// Kinect v2 JointType → kinect32 slot, by name (the numbering differs).
const KINECT32 = ['pelvis', 'spineNavel', 'spineChest', 'neck', 'leftClavicle', 'leftShoulder', 'leftElbow', 'leftWrist',
  'leftHand', 'leftHandTip', 'leftThumb', 'rightClavicle', 'rightShoulder', 'rightElbow', 'rightWrist', 'rightHand',
  'rightHandTip', 'rightThumb', 'leftHip', 'leftKnee', 'leftAnkle', 'leftFoot', 'rightHip', 'rightKnee', 'rightAnkle',
  'rightFoot', 'head', 'nose', 'leftEye', 'leftEar', 'rightEye', 'rightEar'];
const KINECT2 = ['pelvis', 'spineNavel', 'neck', 'head', 'leftShoulder', 'leftElbow', 'leftWrist', 'leftHand',
  'rightShoulder', 'rightElbow', 'rightWrist', 'rightHand', 'leftHip', 'leftKnee', 'leftAnkle', 'leftFoot', 'rightHip',
  'rightKnee', 'rightAnkle'];

/** The recording as kinect32 frames standing 0.95 m in front of the arm, facing it (as crate/tests/human_stream.rs). */
function frames() {
  const lines = fs.readFileSync(CSV, 'utf8').split('\n').filter((l) => l.trim());
  const held = KINECT32.map(() => [0, 0, 0]);
  const out = [];
  let t0;
  for (const line of lines) {
    const c = line.split(',').filter((x) => x.trim()).map(Number);
    t0 ??= c[0];
    KINECT2.forEach((name, j) => {
      const [x, y, z, state] = c.slice(1 + 4 * j, 5 + 4 * j);
      if (state > 0 || out.length === 0) held[KINECT32.indexOf(name)] = [x, -z, y];
    });
    out.push({ t: (c[0] - t0) / 1e7, layout: 'kinect32', keypoints: held.map((p) => [...p]) });
  }
  const pelvis = out[0].keypoints[0];
  const floor = Math.min(out[0].keypoints[20][2], out[0].keypoints[24][2]) - 0.06;
  for (const f of out) {
    f.keypoints = f.keypoints.map(([x, y, z]) => {
      const d = [x - pelvis[0], y - pelvis[1], z - pelvis[2]];
      return [d[1] + 0.95, -d[0], d[2] + pelvis[2] - floor];
    });
  }
  return out;
}

function scenario(person, latency) {
  return {
    robot: { preset: 'panda' },
    q0: [0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8],
    obstacles: [{ id: 'person', shape: person }],
    task: { type: 'trajectory', points: [[0.55, 0, 0.75], [0.6, 0.35, 0.9], [0.6, -0.35, 0.9], [0.55, 0, 0.75]], times: [0, 2, 4, 5.5] },
    controller: { influenceDistance: 0.35 },
    sensing: { person: { latency } },
    dt: 0.01,
    duration: 5.5,
  };
}

function imported(fs_) {
  const text = JSON.stringify({ layout: 'kinect32', frames: fs_.map(({ t, keypoints }) => ({ t, keypoints })) });
  return sa.importTrack(text, { smoothing: 0 });
}

const still = (shape) => {
  const { animation, ...rest } = shape;
  return rest;
};

test('a recording streamed frame by frame moves the arm exactly as the same track', () => {
  const fr = frames();
  const { shape, report } = imported(fr);
  assert.ok(report.fitError.leftWrist.p95 <= 0.03, JSON.stringify(report.fitError.leftWrist));
  const latency = 0.15;
  const track = new sa.World(scenario(shape, latency));
  const stream = new sa.World(scenario(still(shape), latency));
  let next = 0;
  let closest = Infinity;
  for (let k = 0; k < 550; k++) {
    const now = k * 0.01;
    while (next < fr.length && fr[next].t <= now + 1e-12) stream.pushHumanFrame('person', fr[next++]);
    const [a, b] = [track.state(), stream.state()];
    assert.deepEqual(Array.from(stream.q()), Array.from(track.q()), `q at step ${k}`);
    assert.deepEqual(b.qdot, a.qdot, `qdot at step ${k}`);
    assert.equal(b.minClearance, a.minClearance, `minClearance at step ${k}`);
    assert.deepEqual(b.controlPoints, a.controlPoints, `control points at step ${k}`);
    closest = Math.min(closest, track.clearance('person'));
    track.step(0.01);
    stream.step(0.01);
  }
  assert.deepEqual(stream.state().events, track.state().events);
  assert.ok(closest < 0.35, `the arm passes within the influence distance (${closest})`);
  track.free();
  stream.free();
});

test('bad frames are refused naming the field and change nothing', () => {
  const fr = frames();
  const { shape } = imported(fr);
  const w = new sa.World(scenario(still(shape), 0));
  w.pushHumanFrame('person', fr[1]);
  const good = fr[2];
  const before = JSON.stringify([w.state(), w.q()]);
  const bad = (id, frame, re) => {
    assert.throws(() => w.pushHumanFrame(id, frame), re);
    assert.equal(JSON.stringify([w.state(), w.q()]), before, String(re));
  };
  const kp = (k, c, v) => good.keypoints.map((p, i) => (i === k ? p.map((x, j) => (j === c ? v : x)) : p));
  bad('nobody', good, /^Error: obstacleId: no obstacle "nobody"/);
  bad(7, good, /obstacleId/);
  bad('person', { ...good, t: fr[0].t }, /frame\.t: must be after/);
  bad('person', { ...good, t: Number.NaN }, /frame\.t/);
  bad('person', { ...good, keypoints: kp(3, 1, Number.NaN) }, /frame\.keypoints\[3\]\[1\]: not a finite number/);
  bad('person', { ...good, keypoints: kp(5, 2, Infinity) }, /frame\.keypoints\[5\]\[2\]/);
  bad('person', { ...good, keypoints: good.keypoints.slice(1) }, /frame\.keypoints: expected 32 keypoints/);
  bad('person', { ...good, layout: 'coco18' }, /frame\.layout: unknown layout/);
  bad('person', { ...good, layout: 'blazepose33' }, /frame\.keypoints: expected 33 keypoints \(blazepose33\)/);
  bad('person', { ...good, keypoints: Array.from({ length: 10001 }, () => [0, 0, 0]) }, /frame\.keypoints: at most 10000/);
  bad('person', { ...good, confidence: [1, 1] }, /frame\.confidence: expected one per keypoint/);
  bad('person', { ...good, confidence: good.keypoints.map(() => 2) }, /frame\.confidence\[0\]: must be in \[0, 1\]/);
  bad('person', { ...good, extra: 1 }, /frame/);
  bad('person', undefined, /frame/);
  w.free();
});

test('a dropout grows the hand\'s margin at 2.0 m/s and the arm keeps clear of the grown region', () => {
  const fr = frames();
  const { shape } = imported(fr);
  const w = new sa.World(scenario(still(shape), 0));
  const joints = sa.robotPreset('panda').joints;
  // Frames stop coming from 2.0 s to 2.5 s, and from 3.5 s on.
  const dropped = (t) => (t >= 2.0 && t < 2.5) || t >= 3.5;
  let next = 0;
  let last = 0;
  let atHalfSecond = 0;
  let movingSteps = 0;
  let personChecks = 0;
  let nearest = Infinity;
  for (let k = 0; k < 550; k++) {
    const now = k * 0.01;
    while (next < fr.length && fr[next].t <= now + 1e-12) {
      if (!dropped(fr[next].t)) {
        w.pushHumanFrame('person', fr[next]);
        last = fr[next].t;
      }
      next++;
    }
    const before = w.state();
    if (Math.max(...before.qdot.map(Math.abs)) > 1e-9) {
      movingSteps++;
      // A control point answering the person measures to the grown region.
      for (const cp of before.controlPoints.filter((c) => c.obstacle === 'person')) {
        personChecks++;
        nearest = Math.min(nearest, cp.distance);
        assert.ok(cp.distance >= -1e-9, `t ${now}: ${cp.part} ${cp.distance}`);
      }
    }
    before.q.forEach((q, i) => {
      assert.ok(q >= joints[i].min - 1e-9 && q <= joints[i].max + 1e-9, `t ${now}: q[${i}] ${q}`);
      assert.ok(Math.abs(before.qdot[i]) <= joints[i].maxVelocity + 1e-9, `t ${now}: qdot[${i}] ${before.qdot[i]}`);
    });
    w.step(0.01);
    const age = now - last;
    if (age > 0 && k > 0) {
      const margins = w.state().uncertainty.find((u) => u.obstacle === 'person')?.partMargins;
      assert.ok(margins, `t ${now}: the stale person's part margins`);
      const expected = 2.0 * age;
      assert.ok(Math.abs(margins.leftHand / expected - 1) < 0.01, `t ${now}: hand margin ${margins.leftHand} vs ${expected}`);
      if (Math.abs(age - 0.5) < 0.02) atHalfSecond++;
    }
  }
  assert.ok(atHalfSecond >= 1, 'the hand\'s margin was checked at a 0.5 s dropout');
  // The arm works near the grown hand: control points answer the person
  // while it moves, within the influence distance.
  assert.ok(movingSteps > 0 && personChecks > 0, `${movingSteps} moving steps, ${personChecks} checks`);
  assert.ok(nearest < 0.35, `nearest ${nearest}`);
  assert.ok(w.state().events.some((e) => e.kind === 'staleSensing'), 'staleSensing reported');
  w.free();
});

// A live feed stamps each frame with its capture time and delivers it
// `AGE` s later (capture → pose). Without a latency the world sees the
// person at its own time, so every frame arrives already stale and the
// hands' margins have grown by the age; with the measured age set as the
// sensing latency (World.setSensingLatency) the world sees the person that
// long ago: a frame is fresh when it arrives and its parts go stale only
// if the next one is late. Checked on the state after each delivery.
test('the measured latency set by setSensingLatency: a frame is aged from when it was seen, not when it arrived', () => {
  const fr = frames();
  const { shape } = imported(fr);
  const AGE = 0.1;
  const dt = 0.01;
  const run = (latency) => {
    const w = new sa.World(scenario(still(shape), 0));
    if (latency !== null) w.setSensingLatency('person', latency);
    const seen = [];
    let next = 0;
    for (let k = 0; k < 200; k++) {
      const now = k * dt;
      let arrived = false;
      while (next < fr.length && fr[next].t + AGE <= now + 1e-12) {
        w.pushHumanFrame('person', fr[next++]);
        arrived = true;
      }
      w.step(dt);
      if (arrived && next > 1) {
        const u = w.state().uncertainty.find((o) => o.obstacle === 'person');
        seen.push({ stale: u?.stale ?? {}, hand: u?.partMargins?.leftHand ?? u?.radius ?? 0 });
      }
    }
    const events = w.state().events.filter((e) => e.kind === 'staleSensing');
    w.free();
    return { seen, events };
  };
  const late = run(null);
  const timed = run(AGE);
  assert.ok(late.seen.length >= 30 && timed.seen.length === late.seen.length, `${late.seen.length} deliveries`);
  for (const [i, s] of late.seen.entries()) {
    // Unset: the hand's data is at least AGE old when it arrives, its margin grown at 2.0 m/s.
    assert.ok(s.stale.leftHand >= AGE, `delivery ${i}: left hand stale ${s.stale.leftHand} without a latency`);
    assert.ok(s.hand >= 2.0 * AGE - 1e-9, `delivery ${i}: hand margin ${s.hand}`);
    // Set: a delivered frame is at most the steps since its delivery old.
    const fresh = timed.seen[i];
    assert.ok((fresh.stale.leftHand ?? 0) <= 2 * dt + 1e-9, `delivery ${i}: left hand ${fresh.stale.leftHand} s old with the latency set`);
    assert.ok(fresh.hand < s.hand, `delivery ${i}: hand margin ${fresh.hand} < ${s.hand}`);
  }
  assert.ok(late.events.some((e) => e.part === 'leftHand'), 'without a latency the hand turns stale');
  assert.deepEqual(timed.events, [], 'with the latency set no part turns stale');
});

test('setSensingLatency refuses a bad latency or obstacle naming the field, the world unchanged', () => {
  const { shape } = imported(frames());
  const w = new sa.World(scenario(still(shape), 0));
  w.setSensingLatency('person', 0.08);
  const before = JSON.stringify([w.state(), w.q()]);
  const bad = (id, latency, re) => {
    assert.throws(() => w.setSensingLatency(id, latency), re);
    assert.equal(JSON.stringify([w.state(), w.q()]), before, String(re));
  };
  bad('nobody', 0.1, /^Error: obstacleId: no obstacle "nobody"/);
  bad(3, 0.1, /obstacleId/);
  bad('person', -0.01, /^Error: latency: must be a finite number in \[0, 2\] s/);
  bad('person', Number.NaN, /latency/);
  bad('person', Infinity, /latency/);
  bad('person', 2.5, /latency: must be a finite number in \[0, 2\] s/);
  bad('person', '0.1', /latency/);
  w.free();
});
