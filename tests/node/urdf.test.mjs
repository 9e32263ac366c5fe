// The JS contract of `robotFromUrdf(xml, { tip?, base? })` (DESIGN.md),
// against the Node build at crate/pkg-node, on the published URDFs kept with
// their licences in crate/tests/data/urdf.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const sa = require('../../crate/pkg-node/skeleton_avoidance.js');
const urdf = (name) => fs.readFileSync(new URL(`../../crate/tests/data/urdf/${name}`, import.meta.url), 'utf8');

test('robotFromUrdf gives a standard DH spec with joint names, usable everywhere', () => {
  const robot = sa.robotFromUrdf(urdf('ur5_robot.urdf'), { tip: 'ee_link' });
  assert.equal(robot.convention, 'standard');
  assert.deepEqual(robot.jointNames, [
    'shoulder_pan_joint', 'shoulder_lift_joint', 'elbow_joint', 'wrist_1_joint', 'wrist_2_joint', 'wrist_3_joint',
  ]);
  assert.equal(robot.joints.length, 6);
  assert.equal(robot.joints[0].max, 6.28318530718);
  assert.equal(robot.joints[0].maxTorque, 150);
  const q = new Float64Array([0.1, -0.5, 0.7, 0.2, -0.3, 0.4]);
  const fk = sa.forwardKinematics(robot, q);
  assert.equal(fk.endEffector.length, 4);
  const sk = sa.skeleton(robot, q);
  assert.ok(sk.segments.length >= 6);
  // At q = 0 the UR5's ee_link sits at (0.81725, 0.19145, -0.005491) in base_link.
  const zero = sa.forwardKinematics(robot, [0, 0, 0, 0, 0, 0]).endEffector;
  const p = [zero[0][3], zero[1][3], zero[2][3]];
  [0.81725, 0.10915 + 0.0823, 0.089159 - 0.09465].forEach((v, i) => assert.ok(Math.abs(p[i] - v) < 1e-9, `${p}`));
  // The spec round-trips through every function taking a robot.
  const trace = sa.simulate({ robot, q0: [0, -1, 1, 0, 0, 0], obstacles: [], dt: 0.01, duration: 0.05 });
  assert.equal(trace.samples.length > 0, true);
});

test('robotFromUrdf defaults: the root link and the longest chain', () => {
  const robot = sa.robotFromUrdf(urdf('iiwa14_primitive_collision.urdf'));
  assert.equal(robot.jointNames.length, 7);
  assert.equal(robot.joints[0].radius, 0.101);
});

test('robotFromUrdf errors name the element', () => {
  assert.throws(() => sa.robotFromUrdf(42), { message: 'xml: expected the URDF document as a string' });
  assert.throws(() => sa.robotFromUrdf('<robot>'), { message: /^xml: not a readable URDF/ });
  assert.throws(() => sa.robotFromUrdf(urdf('ur5_robot.urdf'), { tip: 'hand' }), { message: 'tip: no link named "hand"' });
  assert.throws(() => sa.robotFromUrdf(urdf('ur5_robot.urdf'), { tipp: 'ee_link' }), { message: /^options\.tipp: unknown field/ });
  const pr2 = urdf('pr2.urdf');
  assert.throws(() => sa.robotFromUrdf(pr2, { tip: 'r_gripper_r_finger_link' }), { message: /^joint "r_gripper_r_finger_joint": mimic joints cannot be imported/ });
  const bad = { ...sa.robotFromUrdf(urdf('ur5_robot.urdf')), jointNames: ['a'] };
  assert.throws(() => sa.forwardKinematics(bad, [0, 0, 0, 0, 0, 0]), { message: 'jointNames: expected 6 names (one per joint), got 1' });
});
