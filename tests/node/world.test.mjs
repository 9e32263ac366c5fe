// The world part of the public JS contract, against crate/pkg-node:
// simulate, World, exampleScenario(Names), benchControlStep.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const sa = require('../../crate/pkg-node/skeleton_avoidance.js');

const NAMES = ['planar-transition', 'lwr4-elbow', 'human-panda', 'human-reach', 'dual-arm-self', 'chattering', 'sliding-point'];

test('exampleScenarioNames lists the shipped examples and each one loads', () => {
  assert.deepEqual(sa.exampleScenarioNames(), NAMES);
  for (const name of NAMES) {
    const s = sa.exampleScenario(name);
    assert.ok(s.robot && Array.isArray(s.obstacles) && s.dt > 0, name);
    // Defaults are filled in.
    assert.equal(typeof s.controller.influenceDistance, 'number', name);
    assert.equal(typeof s.dependability.switchWindow, 'number', name);
  }
  assert.throws(() => sa.exampleScenario('nope'), /name: unknown example "nope"/);
});

test('simulate returns samples and events in the documented shape', () => {
  const s = sa.exampleScenario('planar-transition');
  s.duration = 0.7;
  const trace = sa.simulate(s);
  // Every step from t = 0, and the state at t = duration.
  assert.equal(trace.samples.length, 701);
  assert.equal(trace.samples.at(-1).t, 700 * 0.001, 'the last sample is at t = duration (as steps·dt)');
  trace.samples.forEach((x, k) => assert.equal(x.t, k * 0.001, `sample ${k}`));
  assert.equal(trace.samples[0].qdot.length, 3);
  const first = trace.samples[0];
  assert.equal(first.t, 0);
  assert.equal(first.q.length, 3);
  assert.ok('minClearance' in first);
  const cp = trace.samples[100].controlPoints[0];
  for (const key of ['position', 'link', 'd', 'a', 'obstacle', 'distance']) assert.ok(key in cp, key);
  assert.equal(cp.obstacle, 'ball');
  const kinds = trace.events.map((e) => e.kind);
  assert.ok(kinds.includes('segmentSwitch'));
  assert.ok(kinds.includes('transitionStart'));
  assert.ok(kinds.includes('transitionEnd'));
  const start = trace.events.find((e) => e.kind === 'transitionStart');
  assert.ok(Math.abs(start.t - 0.3) < 1e-9);
  assert.ok(Math.abs(start.duration - 0.3) < 1e-9, 'link 1 → link 3: three DH values, 0.1 s each');
  // Same scenario, same trace.
  assert.deepEqual(sa.simulate(s), trace);
});

test('the chattering example stops the robot and says why', () => {
  const trace = sa.simulate(sa.exampleScenario('chattering'));
  const chatter = trace.events.find((e) => e.kind === 'chattering');
  const stop = trace.events.find((e) => e.kind === 'stop');
  assert.ok(chatter && stop);
  assert.equal(stop.t, chatter.t);
  assert.ok(chatter.t <= 0.5);
  assert.match(stop.reason, /chattering/);
});

test('scenario errors name the JSON path and the reason', () => {
  const base = () => ({ robot: { preset: 'lwr4' }, obstacles: [], dt: 0.001, duration: 0.01 });
  const bad = base();
  bad.obstacles = [
    { id: 'a', shape: { type: 'sphere', center: [0, 0, 1], radius: 0.1 } },
    { id: 'b', shape: { type: 'point', p: [0, 1, 1] } },
    { id: 'c', shape: { type: 'sphere', center: [1, 0, 1], radius: -0.2 } },
  ];
  assert.throws(() => sa.simulate(bad), { message: 'obstacles[2].shape.radius: must be > 0' });
  assert.throws(() => new sa.World(bad), { message: 'obstacles[2].shape.radius: must be > 0' });
  assert.throws(() => sa.simulate({ ...base(), dt: 0 }), { message: 'dt: must be > 0' });
  const short = base();
  short.obstacles = [{ id: 'a', shape: { type: 'sphere', center: [0, NaN, 1], radius: 0.1 } }];
  assert.throws(() => new sa.World(short), { message: 'obstacles[0].shape.center[1]: not a finite number' });
  const robot = { ...base(), robot: { convention: 'standard', joints: [{ a: 0.4, alpha: 'x', d: 0, theta: 0 }] } };
  assert.throws(() => sa.simulate(robot), /^Error: robot\.joints\[0\]\.alpha: expected a number, got/);
  assert.throws(() => sa.simulate({ ...base(), dt: NaN }), /dt: not a finite number/);
  assert.throws(() => sa.simulate({ ...base(), colour: 'red' }), /colour/);
  assert.throws(() => sa.simulate({ ...base(), controller: { mode: 'fast' } }), /controller\.mode/);
  assert.throws(() => sa.simulate({ ...base(), sensing: { ghost: { bound: 1 } } }), /sensing\.ghost: no obstacle/);
  assert.throws(() => sa.simulate(undefined), /scenario/);
  assert.throws(() => sa.simulate([1, 2]), /scenario: expected an object/);
});

test('a scenario camera is checked with the scenario and ignored by the simulation', () => {
  const base = () => ({ robot: { preset: 'lwr4' }, obstacles: [], dt: 0.001, duration: 0.01 });
  assert.throws(() => new sa.World({ ...base(), camera: { pitch: 2 } }), { message: 'camera.pitch: must be within ±1.55 rad (got 2)' });
  assert.throws(() => new sa.World({ ...base(), camera: { frame: [[0, 0, 'x']] } }), /^Error: camera\.frame\[0\]\[2\]/);
  assert.throws(() => new sa.World({ ...base(), camera: { zoom: 2 } }), /camera.*zoom/);
  const withCamera = { ...base(), camera: { yaw: -1.3, pitch: 0.4, frame: [[0.85, 0, 1.6]] } };
  assert.deepEqual(sa.simulate(withCamera).samples.map((s) => s.q), sa.simulate(base()).samples.map((s) => s.q));
  // The shipped human-panda example carries one.
  assert.deepEqual(sa.exampleScenario('human-panda').camera, { yaw: -1.3, pitch: 0.4, frame: [[0.85, 0, 1.6]] });
});

test('a World steps, reports its state and accepts edits', () => {
  const w = new sa.World(sa.exampleScenario('lwr4-elbow'));
  w.advance(0.001, 16);
  assert.ok(Math.abs(w.time - 0.016) < 1e-12);
  const s = w.state();
  for (const key of ['t', 'q', 'qdot', 'minClearance', 'skeleton', 'obstacles', 'controlPoints', 'uncertainty', 'events', 'stopped']) {
    assert.ok(key in s, key);
  }
  assert.equal(s.q.length, 7);
  assert.ok(s.skeleton.nodes.length > 2 && s.skeleton.segments[0].radius.length === 2);
  assert.deepEqual(s.obstacles[0].shape.type, 'sphere');

  w.moveObstacle('ball', [0.0, 0.5, 1.0]);
  assert.deepEqual(w.state().obstacles[0].shape.center, [0.0, 0.5, 1.0]);
  const hit = w.pick([0, 0.5, 3], [0, 0, -1]);
  assert.equal(hit.id, 'ball');
  assert.ok(Math.abs(hit.point[2] - 1.08) < 1e-9);
  assert.equal(w.pick([5, 5, 5], [0, 0, 1]), null);

  w.addObstacle({ id: 'person', shape: { type: 'human', position: [1.2, 0, 0] } });
  assert.equal(w.state().obstacles[1].parts.length, 16, 'pelvis, torso, neck, head, arms, hands, legs, feet');
  w.setObstacleShape('ball', { type: 'capsule', a: [0, 0.5, 1], b: [0, 0.6, 1], radius: 0.05 });
  w.setController({ mode: 'torque', torque: { stiffness: 150 } });
  w.advance(0.001, 10);
  w.removeObstacle('person');
  assert.equal(w.state().obstacles.length, 1);
  w.reset();
  assert.equal(w.time, 0);
  assert.equal(w.state().events.length, 0);
  w.free();
});

test('each control point carries the DH table of its shorter manipulator (fig. 5)', () => {
  for (const name of ['planar-transition', 'lwr4-elbow']) {
    const scenario = sa.exampleScenario(name);
    const robot = scenario.robot.preset ? sa.robotPreset(scenario.robot.preset) : scenario.robot;
    const w = new sa.World(scenario);
    let seen = 0;
    for (let k = 0; k < 40; k++) {
      w.advance(scenario.dt, 50);
      for (const cp of w.state().controlPoints) {
        seen += 1;
        assert.equal(cp.table.length, robot.joints.length);
        // The rows before its link as in the robot, its own row cut to (d', a'), the rows after it zero.
        cp.table.forEach((row, i) => {
          const j = robot.joints[i];
          const expected = i + 1 < cp.link ? { d: j.d, a: j.a } : i + 1 === cp.link ? { d: cp.d, a: cp.a } : { d: 0, a: 0 };
          assert.deepEqual(row, expected, `${name}: row ${i + 1} of a point on link ${cp.link}`);
        });
      }
    }
    assert.ok(seen > 0, `${name}: control points were seen`);
    w.free();
  }
});

test('invalid edits throw with the field and leave the World as it was', () => {
  const w = new sa.World(sa.exampleScenario('lwr4-elbow'));
  w.advance(0.001, 5);
  const before = JSON.stringify(w.state());
  assert.throws(() => w.addObstacle({ id: 'x', shape: { type: 'sphere', center: [0, 0, 0], radius: 0 } }),
    { message: 'obstacle.shape.radius: must be > 0' });
  assert.throws(() => w.addObstacle({ id: 'ball', shape: { type: 'point', p: [0, 0, 0] } }), /already used/);
  assert.throws(() => w.addObstacle({ id: 'x', shape: { type: 'point', p: [0, 0, 0] }, extra: 1 }), /extra/);
  assert.throws(() => w.removeObstacle('nope'), { message: 'id: no obstacle "nope"' });
  assert.throws(() => w.setObstacleShape('ball', { type: 'cone' }), /shape/);
  assert.throws(() => w.moveObstacle('ball', [0, NaN, 0]), /position/);
  assert.throws(() => w.moveObstacle('ball', [0, 0]), /position: expected \[x, y, z\]/);
  assert.throws(() => w.setController({ influenceDistance: -1 }), { message: 'controller.influenceDistance: must be > 0' });
  assert.throws(() => w.setController({ bogus: true }), /bogus/);
  assert.throws(() => w.setController(null), /controller/);
  assert.throws(() => w.setController({ jointWeights: [1, 1, 1] }),
    { message: 'controller.jointWeights: expected 7 values (one per joint), got 3' });
  assert.throws(() => w.setController({ jointWeights: [1, 1, 1, 0, 1, 1, 1] }),
    { message: 'controller.jointWeights[3]: must be > 0' });
  assert.throws(() => w.setController({ protective: { safetyDistance: -0.1 } }), /protective\.safetyDistance/);
  assert.throws(() => w.pick([0, 0, 0], [0, 0, 0]), /direction: must not be zero/);
  assert.throws(() => w.step(0), { message: 'dt: must be > 0' });
  assert.throws(() => w.step(NaN), /dt/);
  assert.throws(() => w.step(1), /dt: must be ≤ 0.1 s/);
  assert.equal(JSON.stringify(w.state()), before);
  w.free();
});

test('the motion of every example stays within the robot\'s limits', () => {
  for (const name of NAMES) {
    const sc = sa.exampleScenario(name);
    sc.sampleEvery = 1;
    const spec = sc.robot.preset ? sa.robotPreset(sc.robot.preset) : sc.robot;
    // A spec without limits gets the documented defaults (revolute joints here).
    const joints = [...spec.joints, ...(spec.branches ?? []).flatMap((b) => b.joints)]
      .map((j) => ({ maxVelocity: 2, maxAcceleration: 10, ...j }));
    const s = sa.simulate(sc).samples;
    let prev = null;
    for (let k = 1; k < s.length; k++) {
      const h = s[k].t - s[k - 1].t;
      const v = s[k].q.map((x, i) => (x - s[k - 1].q[i]) / h);
      v.forEach((x, i) => assert.ok(Math.abs(x) <= joints[i].maxVelocity * (1 + 1e-9), `${name} q̇[${i}] ${x}`));
      if (prev) {
        v.forEach((x, i) => {
          const a = Math.abs(x - prev[i]) / h;
          assert.ok(a <= joints[i].maxAcceleration * (1 + 1e-6), `${name} q̈[${i}] ${a} at ${s[k].t}`);
        });
      }
      prev = v;
    }
  }
});

test('clearanceTo measures a figure against the arm without adding it', () => {
  const w = new sa.World(sa.exampleScenario('planar-transition'));
  const before = JSON.stringify(w.state());
  const far = w.clearanceTo({ type: 'sphere', center: [5, 5, 0], radius: 0.1 });
  const inside = w.clearanceTo({ type: 'sphere', center: w.state().skeleton.nodes[1], radius: 0.05 });
  assert.ok(far > 4, far);
  assert.ok(inside < 0, inside);
  assert.throws(() => w.clearanceTo({ type: 'sphere', center: [0, 0, 0], radius: -1 }), /shape\.radius/);
  assert.equal(JSON.stringify(w.state()), before);
  w.free();
});

test('state(since) returns only new events', () => {
  const w = new sa.World(sa.exampleScenario('chattering'));
  w.advance(0.001, 50);
  const n = w.eventCount;
  assert.ok(n > 2);
  assert.equal(w.state(n - 1).events.length, 1);
  w.advance(0.001, 50);
  assert.equal(w.state(n).events.length, w.eventCount - n);
  w.free();
});

test('benchControlStep runs 1 kHz steps of lwr4 among obstacles', () => {
  const t0 = process.hrtime.bigint();
  const sum = sa.benchControlStep(200);
  const ns = Number(process.hrtime.bigint() - t0) / 200;
  assert.ok(Number.isFinite(sum));
  assert.ok(Number.isFinite(sa.benchControlStep(10, 100)));
  assert.throws(() => sa.benchControlStep(1, 1e6), /obstacles/);
  // Loose: the playground needs 16 steps in a 16.7 ms frame.
  assert.ok(ns < 1e6, `${ns} ns per step`);
});

test('a noisy obstacle reports propagated deviations, a command and a switch probability', () => {
  // The constraints avoidance (the default; this example asks for the
  // paper's repulsion) does not propagate its command.
  const constrained = sa.exampleScenario('chattering');
  constrained.controller.avoidance = 'constraints';
  const plain = new sa.World(constrained);
  plain.advance(0.001, 5);
  assert.equal(plain.state().commandSigma, undefined);
  plain.free();
  const world = new sa.World(sa.exampleScenario('chattering'));
  world.advance(0.001, 5);
  const s = world.state();
  assert.equal(s.command.length, s.q.length);
  assert.equal(s.commandSigma.length, s.q.length);
  assert.ok(s.commandSigma.every((x) => Number.isFinite(x) && x >= 0));
  const p = s.controlPoints.find((c) => c.obstacle === 'blob');
  assert.ok(p.sigma.distance > 0 && p.sigma.repulsion.length === 3, JSON.stringify(p.sigma));
  const u = s.uncertainty[0];
  assert.equal(u.obstacle, 'blob');
  assert.ok(u.switchProbability >= 0 && u.switchProbability <= 1);
  // bound 0.01: σ = 0.01 / √5 along any axis.
  assert.ok(Math.abs(u.sigma - 0.01 / Math.sqrt(5)) < 1e-12, String(u.sigma));
  world.free();
});

test('riskAt gives the clearance and switch probability of a figure without adding it', () => {
  const s = sa.exampleScenario('planar-transition');
  s.q0 = [0, Math.PI / 2, 0];
  const world = new sa.World(s);
  const before = JSON.stringify(world.state());
  // Inside the right-angle elbow, as far from link 1's axis as from link 2's
  // (their radii differ by 1 cm): near the boundary of the two segments.
  const fig = { type: 'point', p: [0.25, 0.15, 0] };
  const even = world.riskAt(fig, { sigma: 0.01 });
  assert.ok(even.switchProbability > 0.2 && even.switchProbability < 0.8, JSON.stringify(even));
  assert.deepEqual([even.segment, even.alternative].sort(), [0, 1]);
  const exact = world.riskAt(fig, {});
  assert.equal(exact.switchProbability, 0);
  assert.ok(Math.abs(exact.clearance - world.clearanceTo(fig)) < 1e-15);
  const far = world.riskAt({ type: 'point', p: [0.25, 0.05, 0] }, { sigma: 0.01 });
  assert.ok(far.switchProbability < 0.01, JSON.stringify(far));
  assert.throws(() => world.riskAt(fig, { sigma: -1 }), /^Error: sensing\.sigma/);
  assert.throws(() => world.riskAt({ type: 'point' }, {}), /shape/);
  assert.equal(JSON.stringify(world.state()), before);
  world.free();
});

test('cheap readouts: q(), qdot(), clearance(id), controller() agree with state() and the defaults', () => {
  const s = sa.exampleScenario('human-panda');
  const w = new sa.World(s);
  try {
    w.advance(0.001, 200);
    const st = w.state();
    assert.ok(w.q() instanceof Float64Array && w.qdot() instanceof Float64Array);
    assert.deepEqual([...w.q()], st.q);
    assert.deepEqual([...w.qdot()], st.qdot);
    assert.ok(st.qdot.some((v) => v !== 0), 'the arm moves');
    // The clearance to one obstacle is the clearance to its figure where it is now.
    for (const o of st.obstacles) {
      assert.equal(w.clearance(o.id), w.clearanceTo(o.shape), o.id);
    }
    assert.ok(Math.min(...st.obstacles.map((o) => w.clearance(o.id))) >= st.minClearance - 1e-12);
    assert.throws(() => w.clearance('nobody'), /^Error: id: no obstacle "nobody"$/);
    assert.throws(() => w.clearance(3), /id: expected a string/);
    // The configuration in effect: the scenario's values, the library's defaults elsewhere.
    const c = w.controller();
    assert.equal(c.influenceDistance, s.controller.influenceDistance);
    const bare = new sa.World({ robot: { preset: 'planar3' }, obstacles: [], dt: 0.001, duration: 1 });
    assert.equal(bare.controller().influenceDistance, 0.3);
    assert.equal(bare.controller().selection, 'perObstacle');
    assert.equal(bare.controller().mode, 'velocity');
    bare.free();
  } finally {
    w.free();
  }
  assert.throws(() => w.q(), /this World has been freed/);
});

test('closestHuman names the person\'s nearest part even while the arm\'s own links are closer', () => {
  // Without the example's sensing noise, so that the sensed person (which
  // `clearance` reads) is where the person is.
  const s = { ...sa.exampleScenario('human-panda'), sensing: undefined };
  const w = new sa.World(s);
  try {
    let seen = 0;
    let behindSelf = 0;
    for (let k = 0; k < 10; k++) {
      w.advance(s.dt, 250);
      const st = w.state();
      if (!st.closestHuman) continue;
      seen += 1;
      assert.match(st.closestHuman.part, /^person:[a-zA-Z]+$/);
      assert.ok(st.closestHuman.distance >= st.minClearance - 1e-12, JSON.stringify(st.closestHuman));
      // clearance() measures where the state's pairs were measured: the
      // last step's q against the person posed at that step's time.
      assert.ok(Math.abs(st.closestHuman.distance - w.clearance('person')) < 1e-9, `t ${st.t}`);
      if (st.closestPart === undefined) behindSelf += 1;
      else assert.equal(st.closestPart, st.closestHuman.part);
    }
    assert.ok(seen > 0 && behindSelf > 0, `seen ${seen}, behind the arm's own links ${behindSelf}`);
  } finally {
    w.free();
  }
});

test('[Symbol.dispose] frees a World once: disposing a freed World does nothing', () => {
  const w = new sa.World({ robot: { preset: 'planar3' }, obstacles: [], dt: 0.001, duration: 1 });
  w.free();
  w[Symbol.dispose]();
  assert.throws(() => w.step(0.001), /this World has been freed/);
  const v = new sa.World({ robot: { preset: 'planar3' }, obstacles: [], dt: 0.001, duration: 1 });
  v[Symbol.dispose]();
  v[Symbol.dispose]();
  assert.throws(() => v.time, /this World has been freed/);
});

test('trace samples carry the clearance to each obstacle, apart from self pairs, as World.clearance reads it after the sample\'s step', () => {
  const s = sa.exampleScenario('human-panda');
  s.duration = 0.3;
  const trace = sa.simulate(s);
  const ids = s.obstacles.map((o) => o.id).sort();
  const w = new sa.World(s);
  const last = trace.samples.length - 1;
  let done = 0;
  try {
    for (const [k, sample] of trace.samples.entries()) {
      assert.deepEqual(Object.keys(sample.clearances).sort(), ids);
      // A sample is the state a step acts on (every `sampleEvery`-th, and
      // one more at the end): its clearances are read after that step.
      const upTo = k < last ? k * s.sampleEvery + 1 : Math.round(s.duration / s.dt) + 1;
      for (; done < upTo; done++) w.step(s.dt);
      for (const id of ids) assert.equal(sample.clearances[id], w.clearance(id), `t = ${sample.t}, ${id}`);
    }
  } finally {
    w.free();
  }
  // The person's clearance is its own; minClearance also counts the floor and self pairs.
  const person = Math.min(...trace.samples.map((x) => x.clearances.person));
  const overall = Math.min(...trace.samples.map((x) => x.minClearance ?? Infinity));
  assert.ok(person > overall, `person ${person}, overall ${overall}`);
});
