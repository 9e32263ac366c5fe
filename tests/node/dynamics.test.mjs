// The dynamics part of the public JS contract (inverseDynamics, massMatrix)
// against crate/pkg-node: Pinocchio's numbers through robotFromUrdf, the
// presets' inertial data, Newton–Euler against M q̈ + (C q̇ + g), and the
// refusals, each naming its field.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const sa = require('../../crate/pkg-node/skeleton_avoidance.js');

const data = new URL('../../crate/tests/data/', import.meta.url);
const read = (p) => fs.readFileSync(new URL(p, data), 'utf8');

/** Largest |a − b| over the largest |b|. */
function relative(a, b) {
  const scale = Math.max(...b.map(Math.abs), 1e-300);
  return Math.max(...a.map((x, k) => Math.abs(x - b[k]))) / scale;
}

const PINOCCHIO = [
  ['panda', 'urdf/panda_collision.urdf'],
  ['ur5', 'urdf/ur5_robot.urdf'],
  ['iiwa14', 'urdf/iiwa14_primitive_collision.urdf'],
  ['random_chain', 'dynamics/random_chain.urdf'],
];

for (const [name, urdf] of PINOCCHIO) {
  test(`${name}: inverseDynamics and massMatrix of robotFromUrdf match Pinocchio to 1e-9`, () => {
    const fixture = JSON.parse(read(`dynamics/${name}.json`));
    const robot = sa.robotFromUrdf(read(urdf), { base: fixture.base, tip: fixture.tip });
    assert.deepEqual(robot.jointNames, fixture.joint_names);
    const options = { gravity: fixture.gravity };
    const [tau, want, m, wantM] = [[], [], [], []];
    for (const s of fixture.samples) {
      const t = sa.inverseDynamics(robot, s.q, s.qdot, s.qddot, options);
      assert.ok(t instanceof Float64Array);
      tau.push(...t);
      want.push(...s.tau);
      m.push(...sa.massMatrix(robot, new Float64Array(s.q)).flat());
      wantM.push(...s.mass_matrix.flat());
    }
    assert.ok(relative(tau, want) < 1e-9, `tau: ${relative(tau, want)}`);
    assert.ok(relative(m, wantM) < 1e-9, `M: ${relative(m, wantM)}`);
  });
}

const dof = (spec) => spec.joints.length + (spec.branches ?? []).reduce((n, b) => n + b.joints.length, 0);

test('Newton–Euler equals M q̈ + (C q̇ + g) on every preset with inertial data, branches and a moved base included', () => {
  const moved = sa.robotPreset('panda');
  const h = Math.sqrt(1 - 0.14);
  moved.base = { position: [0.3, -0.2, 0.5], rotation: [0.2, 0.1, 0.3, h] };
  for (const robot of ['panda', 'ur5', 'iiwa14', 'lwr4', 'dual-arm', moved]) {
    const spec = typeof robot === 'string' ? sa.robotPreset(robot) : robot;
    const n = dof(spec);
    const q = Array.from({ length: n }, (_, k) => 0.3 - 0.17 * k);
    const qdot = Array.from({ length: n }, (_, k) => 0.5 * Math.sin(k + 1));
    const qddot = Array.from({ length: n }, (_, k) => Math.cos(2 * k));
    const m = sa.massMatrix(robot, q);
    assert.equal(m.length, n);
    for (let i = 0; i < n; i++) {
      assert.equal(m[i].length, n);
      assert.ok(m[i][i] > 0);
      for (let j = 0; j < n; j++) assert.ok(Math.abs(m[i][j] - m[j][i]) <= 1e-12 * Math.abs(m[i][i]));
    }
    const tau = sa.inverseDynamics(robot, q, qdot, qddot);
    const bias = sa.inverseDynamics(robot, q, qdot, new Float64Array(n));
    const want = bias.map((b, i) => b + m[i].reduce((s, x, j) => s + x * qddot[j], 0));
    assert.ok(relative([...tau], [...want]) < 1e-12, `${spec.name}: ${relative([...tau], [...want])}`);
  }
});

test('gravity: the default is 9.81 m/s² along −z; options.gravity changes it; at rest without gravity nothing is needed', () => {
  const q = [0, -0.5, 0, -2, 0, 1.5, 0.8];
  const zero = new Float64Array(7);
  const standing = sa.inverseDynamics('panda', q, zero, zero);
  const explicit = sa.inverseDynamics('panda', q, zero, zero, { gravity: [0, 0, -9.81] });
  assert.deepEqual([...standing], [...explicit]);
  assert.ok(Math.abs(standing[1]) > 1, 'the shoulder holds the arm');
  const doubled = sa.inverseDynamics('panda', q, zero, zero, { gravity: [0, 0, -19.62] });
  assert.ok(relative([...doubled], standing.map((x) => 2 * x)) < 1e-12);
  const free = sa.inverseDynamics('panda', q, zero, zero, { gravity: [0, 0, 0] });
  assert.ok(free.every((x) => x === 0));
  // Joint values by name, for a robot with jointNames.
  const robot = sa.robotFromUrdf(read('urdf/ur5_robot.urdf'), { tip: 'tool0' });
  const named = Object.fromEntries(robot.jointNames.map((j, k) => [j, 0.1 * k]));
  const byList = robot.jointNames.map((_, k) => 0.1 * k);
  assert.deepEqual(sa.massMatrix(robot, named), sa.massMatrix(robot, byList));
});

test('a spec may carry inertial data by hand; a robot without it is refused naming its links', () => {
  const spec = {
    convention: 'standard',
    joints: [
      { a: 0.4, alpha: 0, d: 0, theta: 0, inertial: { mass: 2, com: [-0.2, 0, 0], inertia: [0, 0, 0, 0.0267, 0, 0.0267] } },
      { a: 0.3, alpha: 0, d: 0, theta: 0, type: 'prismatic', inertial: { mass: 1 } },
    ],
  };
  // Joint 1 about z (gravity along −z: no torque), joint 2 slides along z:
  // it carries link 2's weight.
  const tau = sa.inverseDynamics(spec, [0.3, 0], [0, 0], [0, 0]);
  assert.ok(Math.abs(tau[0]) < 1e-12);
  assert.ok(Math.abs(tau[1] - 9.81) < 1e-12, String(tau[1]));
  assert.throws(() => sa.inverseDynamics('planar3', [0, 0, 0], [0, 0, 0], [0, 0, 0]),
    { message: 'inertials: no inertial data for links link 1, link 2, link 3' });
  assert.throws(() => sa.massMatrix('stanford', [0, 0, 0.5, 0, 0, 0]), /^Error: inertials: no inertial data for links link 1/);
});

test('bad input is refused with an Error naming the field', () => {
  const q = [0, -0.5, 0, -2, 0, 1.5, 0.8];
  const z = [0, 0, 0, 0, 0, 0, 0];
  const bad = (mass, inertia) => {
    const s = sa.robotPreset('panda');
    s.joints[2].inertial = { mass, com: [0, 0, 0], inertia };
    return s;
  };
  const cases = [
    [() => sa.inverseDynamics('panda', q.slice(1), z, z), /^q: /],
    [() => sa.inverseDynamics('panda', q, z.slice(1), z), /^qdot: expected 7 joint values, got 6$/],
    [() => sa.inverseDynamics('panda', q, z, [...z, 0]), /^qddot: expected 7 joint values, got 8$/],
    [() => sa.inverseDynamics('panda', q, [0, NaN, 0, 0, 0, 0, 0], z), /^qdot\[1\]: not a finite number$/],
    [() => sa.inverseDynamics('panda', q, z, [0, 0, Infinity, 0, 0, 0, 0]), /^qddot\[2\]: not a finite number$/],
    [() => sa.inverseDynamics('panda', [NaN, ...z.slice(1)], z, z), /^q\[0\]: not a finite number$/],
    [() => sa.inverseDynamics('panda', q, z, z, { gravity: [0, 0, NaN] }), /^options\.gravity\[2\]: not a finite number$/],
    [() => sa.inverseDynamics('panda', q, z, z, { gravty: [0, 0, 1] }), /^options\.gravty: /],
    [() => sa.inverseDynamics('panda', q, 'fast', z), /^qdot: /],
    [() => sa.massMatrix(bad(-1, [0.01, 0, 0, 0.01, 0, 0.01]), q), /^joints\[2\]\.inertial\.mass: must be >= 0/],
    [() => sa.massMatrix(bad(1, [-0.01, 0, 0, 0.01, 0, 0.01]), q), /^joints\[2\]\.inertial\.inertia: not positive semi-definite/],
    [() => sa.massMatrix(bad(1, [0.1, 0, 0, 0.01, 0, 0.01]), q), /^joints\[2\]\.inertial\.inertia: principal moments .* violate the triangle inequality/],
    [() => sa.massMatrix(bad(1, [0.01, 0, 0, 0.01, 0]), q), /^joints\[2\]\.inertial\.inertia: /],
    [() => sa.massMatrix({ convention: 'standard', joints: [{ a: 1, alpha: 0, d: 0, theta: 0, inertial: [1, [0, 0, 0]] }] }, [0]),
      /^robot\.joints\[0\]\.inertial: expected an object \{ com, inertia, mass \}, got an array$/],
  ];
  for (const [call, message] of cases) {
    assert.throws(call, (e) => e.constructor === Error && message.test(e.message), String(message));
  }
});
