// The kinematics part of the public JS contract, against crate/pkg-node.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const sa = require('../../crate/pkg-node/skeleton_avoidance.js');

const close = (a, b, tol = 1e-12) => Math.abs(a - b) <= tol;

const PRESETS = ['planar3', 'lwr4', 'iiwa14', 'panda', 'ur5', 'dual-arm', 'stanford'];
const LIMITS = ['min', 'max', 'maxVelocity', 'maxAcceleration', 'maxJerk', 'maxTorque'];

test('robotPreset returns a spec for every documented preset', () => {
  for (const name of PRESETS) {
    const spec = sa.robotPreset(name);
    assert.ok(['standard', 'modified'].includes(spec.convention), name);
    assert.ok(spec.joints.length > 0, name);
  }
  assert.deepEqual(sa.robotPreset('planar3').joints.map((j) => j.a), [0.4, 0.3, 0.2]);
  assert.equal(sa.robotPreset('panda').convention, 'modified');
  assert.deepEqual(sa.presetNames(), PRESETS);
});

test('every preset joint carries finite limits, branches included', () => {
  for (const name of PRESETS) {
    const spec = sa.robotPreset(name);
    const joints = [...spec.joints, ...(spec.branches ?? []).flatMap((b) => b.joints)];
    for (const [k, j] of joints.entries()) {
      for (const field of LIMITS) {
        assert.ok(Number.isFinite(j[field]), `${name} joint ${k} ${field}`);
      }
      assert.ok(j.min < j.max && j.maxVelocity > 0 && j.maxAcceleration > 0 && j.maxJerk > 0 && j.maxTorque > 0);
    }
  }
  assert.equal(sa.robotPreset('dual-arm').branches.flatMap((b) => b.joints).length, 14);
  // Franka's published limits.
  const panda = sa.robotPreset('panda').joints;
  assert.deepEqual(panda.map((j) => j.maxAcceleration), [15, 7.5, 10, 12.5, 15, 20, 20]);
  assert.deepEqual(panda.map((j) => j.maxJerk), [7500, 3750, 5000, 6250, 7500, 10000, 10000]);
  assert.deepEqual(panda.map((j) => j.maxTorque), [87, 87, 87, 87, 12, 12, 12]);
  assert.equal(sa.robotPreset('stanford').joints[2].type, 'prismatic');
});

test('bad limits are refused with the field named', () => {
  const robot = sa.robotPreset('planar3');
  const cases = [
    ['maxVelocity', -1, 'joints[1].maxVelocity: must be > 0'],
    ['maxAcceleration', 0, 'joints[1].maxAcceleration: must be > 0'],
    ['maxJerk', NaN, 'joints[1].maxJerk'],
    ['maxTorque', -5, 'joints[1].maxTorque: must be > 0'],
  ];
  for (const [field, value, message] of cases) {
    const bad = structuredClone(robot);
    bad.joints[1][field] = value;
    assert.throws(() => sa.forwardKinematics(bad, [0, 0, 0]), (e) => e instanceof Error && e.message.includes(message), field);
  }
  const bad = structuredClone(robot);
  bad.joints[0].min = 1;
  bad.joints[0].max = -1;
  assert.throws(() => sa.forwardKinematics(bad, [0, 0, 0]), /joints\[0\]\.min: 1 is above max -1/);
});

test('forwardKinematics matches the closed form of the planar arm', () => {
  const robot = sa.robotPreset('planar3');
  const vectors = [
    [0, 0, 0],
    [0.3, -0.7, 1.1],
    [Math.PI / 2, Math.PI / 2, -Math.PI / 2],
    [-2.1, 0.4, 3.0],
  ];
  for (const q of vectors) {
    const fk = sa.forwardKinematics(robot, q);
    const t1 = q[0], t12 = q[0] + q[1], t123 = q[0] + q[1] + q[2];
    const x = 0.4 * Math.cos(t1) + 0.3 * Math.cos(t12) + 0.2 * Math.cos(t123);
    const y = 0.4 * Math.sin(t1) + 0.3 * Math.sin(t12) + 0.2 * Math.sin(t123);
    const ee = fk.endEffector;
    assert.equal(ee.length, 4);
    assert.ok(close(ee[0][3], x) && close(ee[1][3], y) && close(ee[2][3], 0), `q=${q}`);
    // Rotation about z by θ1+θ2+θ3.
    assert.ok(close(ee[0][0], Math.cos(t123)) && close(ee[1][0], Math.sin(t123)));
    assert.deepEqual(ee[3], [0, 0, 0, 1]);
    assert.equal(fk.origins.length, 4);
    assert.deepEqual(fk.origins[0], [0, 0, 0]);
  }
  // Float64Array and { preset } are accepted too.
  const fk = sa.forwardKinematics({ preset: 'planar3' }, new Float64Array([0, 0, 0]));
  assert.ok(close(fk.endEffector[0][3], 0.9));
});

test('skeleton and controlPoint follow the contract', () => {
  const robot = sa.robotPreset('lwr4');
  const q = [0.1, 0.5, -0.2, -1.2, 0.3, 0.8, 0];
  const sk = sa.skeleton(robot, q);
  assert.equal(sk.nodes.length, 5);
  assert.equal(sk.segments.length, 4);
  for (const s of sk.segments) {
    assert.ok(s.link >= 1 && s.link <= 7 && s.radius.length === 2);
  }
  const cp = sa.controlPoint(robot, q, { link: 3, d: 0.2, a: 0 });
  assert.equal(cp.jTheta.length, 3);
  assert.equal(cp.jTheta[0].length, 7);
  for (const m of [cp.jTheta, cp.jA, cp.jD]) {
    for (const row of m) for (let k = 3; k < 7; k++) assert.equal(row[k], 0);
  }
  // J_θ against a finite difference of the position.
  const h = 1e-6;
  for (let k = 0; k < 3; k++) {
    const qp = q.slice(); qp[k] += h;
    const qm = q.slice(); qm[k] -= h;
    const pp = sa.controlPoint(robot, qp, { link: 3, d: 0.2, a: 0 }).position;
    const pm = sa.controlPoint(robot, qm, { link: 3, d: 0.2, a: 0 }).position;
    for (let r = 0; r < 3; r++) {
      assert.ok(close((pp[r] - pm[r]) / (2 * h), cp.jTheta[r][k], 1e-7));
    }
  }
  // The paper's planar example: the middle of link 3 is (3, 0, 0.1).
  const planar = sa.robotPreset('planar3');
  const mid = sa.skeletonPoint(planar, [0.3, -0.7, 1.1], { segment: 2, t: 0.5 });
  assert.equal(mid.link, 3);
  assert.ok(close(mid.a, 0.1) && mid.d === 0);
});

test('bad input throws an Error naming the field', () => {
  const robot = sa.robotPreset('lwr4');
  const throwsWith = (fn, re) => assert.throws(fn, (e) => e instanceof Error && re.test(e.message));
  throwsWith(() => sa.forwardKinematics(robot, [0, 0, 0]), /^q: expected 7 joint values, got 3/);
  throwsWith(() => sa.forwardKinematics(robot, [0, 0, NaN, 0, 0, 0, 0]), /^q\[2\]: not a finite number/);
  throwsWith(() => sa.forwardKinematics(robot, 'hello'), /^q: expected an array/);
  throwsWith(() => sa.forwardKinematics(robot, [0, 0, 'x', 0, 0, 0, 0]), /^q\[2\]: not a number/);
  throwsWith(() => sa.forwardKinematics(robot, undefined), /^q: expected an array/);
  const bad = structuredClone(robot);
  bad.joints[3].alpha = NaN;
  throwsWith(() => sa.forwardKinematics(bad, [0, 0, 0, 0, 0, 0, 0]), /^joints\[3\]\.alpha: not a finite number/);
  bad.joints[3].alpha = 'x';
  throwsWith(() => sa.forwardKinematics(bad, [0, 0, 0, 0, 0, 0, 0]), /^joints\[3\]\.alpha: expected a number, got the string/);
  throwsWith(() => sa.forwardKinematics({ convention: 'standard', joints: [] }, []), /^joints: the DH table is empty/);
  throwsWith(() => sa.robotPreset('kuka'), /^preset: unknown robot "kuka"/);
  throwsWith(() => sa.forwardKinematics({ ...robot, base: { position: [0, 0, 0], rotation: [0, 0, 0, 0] } }, [0, 0, 0, 0, 0, 0, 0]), /^base\.rotation: degenerate/);
  throwsWith(() => sa.controlPoint(robot, [0, 0, 0, 0, 0, 0, 0], { link: 9, d: 0, a: 0 }), /^point\.link: 9 is not a link of this robot \(links 1 to 7\)/);
  throwsWith(() => sa.controlPoint(robot, [0, 0, 0, 0, 0, 0, 0], { link: 3, d: 0.5, a: 0 }), /^point\.d: 0\.5 is outside the link's span/);
  throwsWith(() => sa.forwardKinematics(42, [0]), /^robot: expected a robot spec object/);
});

test('a row radius per segment: { d?, a?, extension? }, the old forms unchanged', () => {
  const row = (radius) => ({ convention: 'standard', joints: [{ a: 0.3, alpha: 0, d: 0.2, theta: 0, extension: 0.1, radius }] });
  const radii = (radius) => sa.skeleton(row(radius), [0]).segments.map((s) => [s.part, s.radius]);
  assert.deepEqual(radii([0.07, 0.04]), [['d', [0.07, 0.04]], ['extension', [0.07, 0.04]], ['a', [0.07, 0.04]]]);
  assert.deepEqual(radii(0.07), [['d', [0.07, 0.07]], ['extension', [0.07, 0.07]], ['a', [0.07, 0.07]]]);
  // A part left out gets 0.05.
  assert.deepEqual(radii({ d: [0.1, 0.2], a: 0.03 }), [['d', [0.1, 0.2]], ['extension', [0.05, 0.05]], ['a', [0.03, 0.03]]]);
  const throwsWith = (fn, re) => assert.throws(fn, (e) => e instanceof Error && re.test(e.message));
  throwsWith(() => sa.skeleton(row({ d: [0.1, -0.2] }), [0]), /^joints\[0\]\.radius\.d\[1\]: /);
  throwsWith(() => sa.skeleton(row({ b: 0.1 }), [0]), /^joints\[0\]\.radius: expected a number, \[r0, r1\] or \{ d\?, a\?, extension\? \}/);
});
