// The boundary fuzz layer: every export and every World method,
// called by a seeded hostile caller for a bounded time. It asserts that
//   * only plain `Error`s are thrown (never a wasm `RuntimeError`), each
//     naming a field (`field: reason`) or the freed World, in the project's
//     words (never serde's `expected struct X`, `variant`, `f64`);
//   * every accepted result is finite (no NaN or ±Infinity anywhere);
//   * a refused World edit leaves `state()` byte-identical;
//   * no call takes more than a second of CPU;
//   * the module, and the World, still answer after every call.
// It prints a table of calls and failures per function and method.
//
//   FUZZ_SEED=n FUZZ_SECONDS=s node --test tests/fuzz/
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createRequire } from 'node:module';
import { rng, hostile, mutate } from './values.mjs';

const require = createRequire(import.meta.url);
const sa = require('../../crate/pkg-node/skeleton_avoidance.js');

const SEED = Number(process.env.FUZZ_SEED ?? 13);
const SECONDS = Number(process.env.FUZZ_SECONDS ?? 40);
const MIN_CALLS = Number(process.env.FUZZ_MIN_CALLS ?? 50000);

// Valid inputs to start from (each mutated into hostile variants).
const PRIMITIVES = [
  { type: 'point', p: [0, 0, 1] },
  { type: 'segment', a: [0, 0, 0], b: [1, 0, 0] },
  { type: 'sphere', center: [0.5, 0.2, 0], radius: 0.1 },
  { type: 'capsule', a: [0, 1, 0], b: [1, 1, 0], radius: 0.05 },
  { type: 'plane', normal: [0, 0, 1], offset: 0.1 },
  { type: 'rectangle', center: [0, 0, 1], axes: [[1, 0, 0], [0, 1, 0]], halfExtents: [0.2, 0.1] },
  { type: 'disk', center: [0, 0, 2], normal: [0, 0, 1], radius: 0.3 },
  { type: 'polygon', vertices: [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0.0]] },
  { type: 'box', center: [2, 0, 0], halfExtents: [0.1, 0.2, 0.3], rotation: [0, 0, 0, 1] },
  { type: 'convexHull', points: [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]] },
];
const ROBOTS = [
  'planar3',
  { preset: 'lwr4' },
  sa.robotPreset('planar3'),
  { convention: 'standard', joints: [{ a: 0.4, alpha: 0, d: 0, theta: 0 }, { a: 0.3, alpha: 0, d: 0, theta: 0, radius: [0.05, 0.03] }] },
];
const Q = { planar3: [0.1, 0.2, 0.3], lwr4: [0, 0.3, 0, -1, 0, 0.5, 0] };
// Robots with inertial data (for the dynamics): a preset, and a spec with a
// prismatic row given by hand.
const DYNAMIC = [
  [{ preset: 'lwr4' }, Q.lwr4],
  [{ convention: 'modified', joints: [
    { a: 0, alpha: 0, d: 0.3, theta: 0, inertial: { mass: 2, com: [0.1, 0, 0], inertia: [0.01, 0, 0, 0.02, 0, 0.02] } },
    { a: 0.4, alpha: 1.5707963267948966, d: 0, theta: 0, type: 'prismatic', inertial: { mass: 1 } },
  ] }, [0.1, 0.2]],
];
// Each example's own duration: a fresh World may start anywhere in it (a
// person beside the arm, control points answering noisy obstacles).
const DURATIONS = sa.exampleScenarioNames().map((n) => sa.exampleScenario(n).duration);
const SCENARIOS = sa.exampleScenarioNames().map((n) => {
  const s = sa.exampleScenario(n);
  s.duration = Math.min(s.duration, 20 * s.dt);
  return s;
});
// Rows of a two-run study (monteCarloMerge's input).
const ROWS = sa.monteCarloRuns(SCENARIOS[0], { seed: 1, count: 2 });
const OBSTACLE = { id: 'fuzz', shape: { type: 'sphere', center: [0.3, 0.3, 0.3], radius: 0.05 }, motion: { type: 'linear', velocity: [0, 0, 0.1] } };
const CONTROLLER = { mode: 'torque', influenceDistance: 0.3, damping: { epsilon: 0.05, lambdaMax: 0.05 } };
const URDF = `<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0 0 0.3"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>`;

/** An argument: valid, a mutated valid one, or anything. */
function arg(r, valid) {
  const x = r.next();
  if (x < 0.3) return typeof valid === 'function' ? valid() : valid;
  if (x < 0.75) return mutate(r, typeof valid === 'function' ? valid() : valid);
  return hostile(r);
}

const robotQ = (r) => {
  const robot = r.pick(ROBOTS);
  const name = typeof robot === 'string' ? robot : robot.preset ?? robot.name ?? 'planar2';
  const q = Q[name] ?? (name === 'planar2' ? [0.1, 0.2] : [0.1, 0.2, 0.3]);
  return [robot, q];
};

/** A human with an animation, and a short COCO-17 track (JSON text). */
const HUMAN = { type: 'human', position: [1, 0, 0], heading: 3, animation: { clip: 'wave' } };
const TRACK = JSON.stringify({
  layout: 'coco17',
  frames: [0, 0.1, 0.2].map((t) => ({
    t,
    keypoints: Array.from({ length: 17 }, (_, k) => [1 + 0.01 * k, 0.1 * (k % 2 ? 1 : -1), 1.6 - 0.08 * k + 0.01 * t]),
  })),
});

/** The free functions, each with a generator of (mostly hostile) arguments. */
const FUNCTIONS = {
  robotPreset: (r) => [arg(r, r.pick(sa.presetNames()))],
  presetNames: () => [],
  exampleScenarioNames: () => [],
  exampleScenario: (r) => [arg(r, r.pick(sa.exampleScenarioNames()))],
  forwardKinematics: (r) => { const [ro, q] = robotQ(r); return [arg(r, ro), arg(r, q)]; },
  skeleton: (r) => { const [ro, q] = robotQ(r); return [arg(r, ro), arg(r, q)]; },
  controlPoint: (r) => { const [ro, q] = robotQ(r); return [arg(r, ro), arg(r, q), arg(r, { link: 2, d: 0, a: 0.1 }), r.chance(0.5) ? undefined : arg(r, { qdot: q.map(() => 0.1), aRate: 0.1 })]; },
  skeletonPoint: (r) => { const [ro, q] = robotQ(r); return [arg(r, ro), arg(r, q), arg(r, { segment: 0, t: 0.5 })]; },
  inverseDynamics: (r) => {
    const [ro, q] = r.pick(DYNAMIC);
    return [arg(r, ro), arg(r, q), arg(r, q.map(() => 0.5)), arg(r, q.map(() => -1)), r.chance(0.5) ? undefined : arg(r, { gravity: [0, 0, -9.81] })];
  },
  massMatrix: (r) => { const [ro, q] = r.pick(DYNAMIC); return [arg(r, ro), arg(r, q)]; },
  distance: (r) => [arg(r, r.pick(PRIMITIVES)), arg(r, r.pick(PRIMITIVES))],
  referencePoint: (r) => [arg(r, r.pick(PRIMITIVES))],
  translateShape: (r) => [arg(r, r.pick(PRIMITIVES)), arg(r, [0.1, -0.2, 0.3])],
  moveHumanHand: (r) => [arg(r, HUMAN), arg(r, r.pick(['left', 'right'])), arg(r, [0.05, -0.1, 0.2])],
  importTrack: (r) => [arg(r, TRACK), r.chance(0.5) ? undefined : arg(r, { smoothing: 0.02, maxGap: 0.3 })],
  simulate: (r) => [arg(r, r.pick(SCENARIOS))],
  planPath: (r) => { const s = r.pick(SCENARIOS); return [arg(r, s), arg(r, s.q0 ?? [0, 0, 0]), r.chance(0.5) ? undefined : arg(r, { rounds: 50, seed: r.int(5) })]; },
  robotFromUrdf: (r) => [arg(r, URDF), r.chance(0.5) ? undefined : arg(r, { tip: 'b' })],
  fitUrdf: (r) => [arg(r, URDF), r.chance(0.5) ? arg(r, { tip: 'b', meshes: {} }) : { meshes: { 'm.stl': new Uint8Array(r.int(200)).map(() => r.int(256)) } }],
  importUrdf: (r) => [arg(r, URDF), r.chance(0.5) ? undefined : arg(r, r.chance(0.5) ? { tip: 'b' } : { radii: { b: 0.03 } })],
  benchControlStep: (r) => [arg(r, r.int(3)), r.chance(0.5) ? undefined : arg(r, r.int(3))],
  benchKinematicsStep: (r) => [arg(r, 'planar3'), arg(r, r.int(3))],
  monteCarlo: (r) => [arg(r, r.pick(SCENARIOS)), arg(r, { runs: 1 + r.int(2), seed: r.int(5), rows: r.chance(0.5) })],
  monteCarloRuns: (r) => [arg(r, r.pick(SCENARIOS)), arg(r, { seed: r.int(5), from: r.int(3), count: 1 + r.int(2) })],
  monteCarloMerge: (r) => [arg(r, ROWS), r.chance(0.5) ? undefined : arg(r, { rows: true })],
};

/** World methods: [name, args, edits?]. */
const METHODS = [
  ['step', (r) => [arg(r, 0.001)]],
  ['advance', (r) => [arg(r, 0.001), arg(r, r.int(5))]],
  ['state', (r) => [r.chance(0.5) ? undefined : arg(r, 0)]],
  ['addObstacle', (r) => [arg(r, { ...OBSTACLE, id: `o${r.int(4)}` })], true],
  ['removeObstacle', (r) => [arg(r, r.pick(['o0', 'o1', 'ball', 'person', 'floor']))], true],
  ['setObstacleShape', (r) => [arg(r, r.pick(['o0', 'ball', 'person'])), arg(r, r.pick(PRIMITIVES))], true],
  ['moveObstacle', (r) => [arg(r, r.pick(['o0', 'ball', 'person'])), arg(r, [0.2, 0.1, 0.3])], true],
  ['setController', (r) => [arg(r, CONTROLLER)], true],
  ['riskAt', (r) => [arg(r, r.pick(PRIMITIVES)), r.chance(0.5) ? undefined : arg(r, { bound: 0.01, sigma: 0.005 })]],
  ['pick', (r) => [arg(r, [0, 0, 2]), arg(r, [0, 0, -1])]],
  ['pickSkeleton', (r) => [arg(r, [0.3, 0, 2]), arg(r, [0, 0, -1])]],
  ['reset', () => []],
  ['q', () => []],
  ['qdot', () => []],
  ['controller', () => []],
  ['clearance', (r) => [arg(r, r.pick(['o0', 'ball', 'person']))]],
  ['setSensingLatency', (r) => [arg(r, r.pick(['o0', 'ball', 'person'])), arg(r, r.pick([0, 0.05, 0.1, 2]))], true],
  ['pushHumanFrame', (r) => [arg(r, r.pick(['o0', 'ball', 'person'])), arg(r, {
    t: r.int(50) * 0.01,
    layout: r.pick(['coco17', 'body25', 'blazepose33']),
    keypoints: Array.from({ length: 17 }, (_, i) => [0.8 + 0.01 * r.int(5), 0.05 * (i % 5) - 0.1, 0.1 + 0.09 * i]),
  })], true],
];

/** Where a non-finite number hides in `v`, or null. */
function nonFinite(v, path = '') {
  if (typeof v === 'number') return Number.isFinite(v) ? null : `${path} = ${v}`;
  if (v && typeof v === 'object') {
    for (const [k, x] of Object.entries(v)) {
      const bad = nonFinite(x, `${path}.${k}`);
      if (bad) return bad;
    }
  }
  return null;
}

/** Names the field (`path: reason`) or the freed World. */
const NAMES_FIELD = /^([A-Za-z_$][\w$]*|\[\d+\])([.\w$\[\]-]*): \S|^this World has been freed$/;

/** serde's words for Rust types, which a caller should never read. */
const JARGON = /expected struct|untagged enum|\bvariant\b|string or map|internally tagged|\bsequence\b|Option value|unit value|\b(f32|f64|[iu](8|16|32|64|size))\b/;

const sanity = () => sa.distance({ type: 'point', p: [0, 0, 0] }, { type: 'point', p: [0, 0, 1] }).distance === 1;

const describe = (args) =>
  args.map((a) => {
    try {
      return typeof a === 'bigint' || typeof a === 'symbol' ? String(a) : JSON.stringify(a)?.slice(0, 120);
    } catch {
      try {
        return Object.prototype.toString.call(a);
      } catch {
        return '(unreadable)';
      }
    }
  });

test(`boundary fuzz: every export and World method, seed ${SEED}, ${SECONDS} s`, () => {
  const r = rng(SEED);
  const stats = { calls: 0, accepted: 0, refused: 0, jargon: 0, editsRefused: 0, freedCalls: 0, slowest: 0 };
  const failures = [];
  // Per function or method: calls, accepted, refused, and each kind of failure.
  const table = new Map();
  const row = (name) => {
    const key = name.replace(/^freed /, '');
    if (!table.has(key)) table.set(key, { calls: 0, accepted: 0, refused: 0, trap: 0, badThrow: 0, hang: 0, nonFinite: 0, poisoned: 0, other: 0 });
    return table.get(key);
  };
  const KINDS = { 'bad throw': 'badThrow', hang: 'hang', 'non-finite output': 'nonFinite', 'refused edit changed the World': 'poisoned', 'World unusable': 'poisoned', 'module broken': 'poisoned' };
  const fail = (what, name, args, detail) => {
    const r = row(name);
    if (what === 'bad throw' && detail.startsWith('RuntimeError')) r.trap++;
    else r[KINDS[what] ?? 'other']++;
    if (failures.length < 20) failures.push(`${what} in ${name}(${describe(args).join(', ')}): ${detail}`);
  };
  const call = (name, fn, args, self) => {
    stats.calls++;
    row(name).calls++;
    // A hang is judged on the CPU time the call burns (the machines are
    // shared: wall time also counts other processes).
    const cpu0 = process.cpuUsage();
    const t = performance.now();
    let out;
    let err;
    try {
      out = fn.apply(self, args);
    } catch (e) {
      err = e;
    }
    const wall = performance.now() - t;
    const cpu = process.cpuUsage(cpu0);
    const ms = (cpu.user + cpu.system) / 1000;
    if (ms > stats.slowest) {
      stats.slowest = ms;
      stats.slowestCall = `${name}, ${wall.toFixed(0)} ms wall`;
    }
    if (ms > 1000) fail('hang', name, args, `${ms.toFixed(0)} ms of CPU (${wall.toFixed(0)} ms wall)`);
    if (err !== undefined) {
      stats.refused++;
      row(name).refused++;
      if (!(err instanceof Error) || err instanceof WebAssembly.RuntimeError || err.constructor !== Error) {
        fail('bad throw', name, args, `${err?.constructor?.name}: ${err?.message ?? err}`);
      } else if (!NAMES_FIELD.test(err.message)) {
        fail('message names no field', name, args, err.message);
      } else if (JARGON.test(err.message)) {
        stats.jargon++;
        fail('message in serde words', name, args, err.message);
      }
    } else {
      stats.accepted++;
      row(name).accepted++;
      const bad = nonFinite(out);
      if (bad) fail('non-finite output', name, args, bad);
    }
    if (!sanity()) fail('module broken', name, args, 'distance() no longer answers');
    return err === undefined;
  };

  // Half the fresh Worlds start at a random time of their example (up to
  // 3 000 steps in): the states edits meet mid-run, not only at t = 0.
  let start = 0;
  const fresh = () => {
    const k = r.int(SCENARIOS.length);
    const scenario = structuredClone(SCENARIOS[k]);
    const w = new sa.World(scenario);
    if (r.chance(0.5)) w.advance(scenario.dt, r.int(Math.min(3000, Math.round(DURATIONS[k] / scenario.dt))));
    start = w.time;
    return w;
  };
  let world = fresh();
  const deadline = performance.now() + SECONDS * 1000;
  while ((performance.now() < deadline || stats.calls < MIN_CALLS) && failures.length < 20) {
    if (performance.now() > deadline + 120000) break;
    const x = r.next();
    if (x < 0.45) {
      const name = r.pick(Object.keys(FUNCTIONS));
      call(name, sa[name], FUNCTIONS[name](r), null);
    } else if (x < 0.97) {
      const [name, gen, edits] = r.pick(METHODS);
      const args = gen(r);
      const before = edits ? JSON.stringify(world.state()) : null;
      const ok = call(`World.${name}`, world[name], args, world);
      if (edits && !ok) {
        stats.editsRefused++;
        if (JSON.stringify(world.state()) !== before) fail('refused edit changed the World', `World.${name}`, args, 'state() differs');
      }
      try {
        world.state(world.eventCount);
      } catch (e) {
        fail('World unusable', `World.${name}`, args, e?.message ?? String(e));
        world = fresh();
      }
      if (world.time > start + 1) {
        world.free();
        world = fresh();
      }
    } else if (x < 0.985) {
      call('new World', (s) => new sa.World(s), [arg(r, structuredClone(r.pick(SCENARIOS)))], null);
    } else {
      // Use after free, and a second free.
      world.free();
      const [name, gen] = r.pick(METHODS);
      stats.freedCalls++;
      call(`freed World.${name}`, world[name], gen(r), world);
      call('freed World.free', world.free, [], world);
      world = fresh();
    }
  }
  world.free();
  const cols = ['calls', 'accepted', 'refused', 'trap', 'badThrow', 'hang', 'nonFinite', 'poisoned', 'other'];
  console.log(`${'function or method'.padEnd(24)} ${cols.map((c) => c.padStart(9)).join(' ')}`);
  for (const [name, r] of [...table].sort((a, b) => a[0].localeCompare(b[0]))) {
    console.log(`${name.padEnd(24)} ${cols.map((c) => String(r[c]).padStart(9)).join(' ')}`);
  }
  console.log(
    `fuzz: seed ${SEED}: ${stats.calls} calls, ${stats.accepted} accepted, ${stats.refused} refused with an Error ` +
      `(${stats.editsRefused} refused World edits left state() identical, ${stats.freedCalls} calls on freed Worlds), ` +
      `slowest call ${stats.slowest.toFixed(0)} ms of CPU (${stats.slowestCall}), ${failures.length} failures`,
  );
  assert.deepEqual(failures, []);
  assert.ok(stats.calls >= MIN_CALLS, `only ${stats.calls} calls`);
});

test('the throwing getter that used to poison a World leaves it usable', () => {
  const w = new sa.World(sa.exampleScenario('planar-transition'));
  for (let k = 0; k < 3000; k++) {
    assert.throws(() => w.setController({ get mode() { throw new Error('boom'); } }), /^Error: controller\.mode: could not be read \(boom\)$/);
    assert.throws(() => sa.distance({ type: 'point', get p() { throw new Error('boom'); } }, { type: 'point', p: [0, 0, 0] }), /a\.p: could not be read/);
  }
  // A getter that steps the World it is being passed to.
  w.addObstacle({ id: 'x', get shape() { w.step(0.001); return { type: 'point', p: [1, 1, 1] }; } });
  w.step(0.001);
  assert.ok(w.state().obstacles.some((o) => o.id === 'x'));
  w.free();
  assert.throws(() => w.step(0.001), /^Error: this World has been freed$/);
  w.free(); // a second free does nothing
});

test('scalars are not coerced and counts do not wrap', () => {
  const w = new sa.World(sa.exampleScenario('planar-transition'));
  assert.throws(() => w.step('0.001'), /dt: expected a number, got a string/);
  assert.throws(() => w.step([0.001]), /dt: expected a number, got an object/);
  assert.throws(() => w.step(true), /dt: expected a number, got a boolean/);
  assert.throws(() => w.advance(0.001, NaN), /steps: not a finite number/);
  assert.throws(() => w.advance(0.001, 2 ** 32), /steps: at most 100000/);
  assert.throws(() => w.advance(0.001, -1), /steps: must be >= 0/);
  assert.throws(() => w.state('x'), /since: expected a number/);
  assert.throws(() => sa.benchControlStep(-1), /iterations: must be >= 0/);
  assert.throws(() => sa.benchKinematicsStep('lwr4', 2 ** 40), /iterations: at most/);
  assert.throws(() => sa.exampleScenario(0), /name: expected a string, got a number/);
  assert.throws(() => w.removeObstacle(['ball']), /id: expected a string, got an object/);
  w.free();
});

test('messages say what was expected in the project\'s words', () => {
  const w = new sa.World(sa.exampleScenario('planar-transition'));
  const base = () => sa.exampleScenario('planar-transition');
  const sphere = { type: 'sphere', center: [0, 0, 0], radius: 0.1 };
  const cases = [
    [() => w.setController({ damping: 5 }), 'controller.damping: expected an object { epsilon, lambdaMax }, got 5'],
    [() => w.setController({ damping: [0.1] }), 'controller.damping: expected an object { epsilon, lambdaMax }, got an array'],
    [() => w.setController({ mode: 5 }), 'controller.mode: expected a string, got 5'],
    [() => w.setController({ mode: 'fast' }), 'controller.mode: unknown value "fast" (known: velocity, torque, clik2)'],
    [() => w.addObstacle({ id: 'm', shape: sphere, motion: { type: 'waypoints', points: [[0, 0, 0], []], times: [0, 1] } }),
      'obstacle.motion.points[1]: expected an array of length 3, got 0 elements'],
    [() => w.addObstacle({ id: 'm', shape: sphere, motion: { type: 'linear' } }), 'obstacle.motion: missing `velocity` (a linear motion needs velocity)'],
    [() => w.addObstacle({ id: 'm', shape: sphere, motion: { type: 'spin' } }),
      'obstacle.motion.type: unknown motion "spin" (known: static, linear, waypoints, circular)'],
    [() => w.addObstacle({ id: 'm', shape: { type: 'human', position: [0, 0] } }), 'obstacle.shape.position: expected an array of length 3, got 2 elements'],
    [() => w.addObstacle({ id: 'm', shape: ['point', [0, 0, 0]] }), /^obstacle\.shape: expected an object/],
    [() => new sa.World({ ...base(), task: { type: 'goal', position: [1, 2] } }), 'task.position: expected an array of length 3, got 2 elements'],
    [() => new sa.World({ ...base(), task: [{ type: 'goal', position: [1, 2] }] }), 'task[0].position: expected an array of length 3, got 2 elements'],
    [() => new sa.World({ ...base(), task: 5 }), 'task: expected a task { type, … } or a list of tasks'],
    [() => new sa.World({ ...base(), robot: { convention: 'standard', base: [[0, 0, 0], [0, 0, 0, 1]], joints: [{ a: 1, alpha: 0, d: 0, theta: 0 }] } }),
      'robot.base: expected an object { position, rotation }, got an array'],
    [() => new sa.World({ ...base(), robot: { convention: 'standard', joints: [{ a: 1, alpha: 0, d: 0, theta: 0, type: 5 }] } }),
      'robot.joints[0].type: expected a string, got 5'],
    [() => sa.controlPoint('planar3', [0, 0, 0], { link: 1.5, d: 0, a: 0 }), 'point.link: expected a whole number ≥ 0, got 1.5'],
  ];
  for (const [f, expected] of cases) {
    assert.throws(f, (e) => {
      if (typeof expected === 'string') assert.equal(e.message, expected);
      else assert.match(e.message, expected);
      assert.doesNotMatch(e.message, JARGON);
      return true;
    });
  }
  w.free();
});
