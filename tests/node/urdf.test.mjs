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

test('importUrdf reports what it read, defaulted and left out; the spec carries the values used', () => {
  const xml = urdf('iiwa14_primitive_collision.urdf');
  const { robot, report } = sa.importUrdf(xml, { tip: 'iiwa_link_ee' });
  assert.deepEqual(robot, sa.robotFromUrdf(xml, { tip: 'iiwa_link_ee' }));
  assert.equal(report.joints.length, 7);
  assert.deepEqual(report.joints.map((j) => j.name), robot.jointNames);
  for (const [k, j] of robot.joints.entries()) {
    // Every value the library uses is in the spec, none left undefined.
    for (const field of ['radius', 'maxVelocity', 'maxAcceleration', 'maxJerk', 'maxTorque']) {
      assert.equal(typeof j[field], 'number', `joints[${k}].${field}`);
    }
    assert.equal(j.radius, report.joints[k].radius);
  }
  // Links 6 and 7 carry only meshes: the default radius, and the report says so.
  assert.deepEqual(report.joints.slice(5).map((j) => j.radiusFrom), ['default', 'default']);
  assert.ok(report.linksWithoutPrimitive.includes('iiwa_link_7'));
  assert.deepEqual(report.joints[0].defaulted, ['maxJerk'], 'the file gives velocity, effort and acceleration');
  assert.deepEqual(report.startContacts, []);
  // A radius per link, by URDF name.
  const thin = sa.importUrdf(xml, { tip: 'iiwa_link_ee', radii: { iiwa_link_7: 0.04 } });
  assert.equal(thin.robot.joints[6].radius, 0.04);
  assert.equal(thin.report.joints[6].radiusFrom, 'override');
  assert.throws(() => sa.importUrdf(xml, { radii: { iiwa_link_99: 0.04 } }), /^Error: radii\.iiwa_link_99: no link named "iiwa_link_99"$/);
  // DH values without rounding dust.
  for (const j of robot.joints) for (const v of [j.a, j.alpha, j.d, j.theta]) assert.ok(v === 0 ? !Object.is(v, -0) : Math.abs(v) > 1e-14, `${v}`);
});

test('an import that starts in self-collision names the links, by their URDF names', () => {
  const xml = urdf('iiwa14_primitive_collision.urdf').replace(
    '<link name="iiwa_link_7">',
    '<link name="iiwa_link_7"><collision><geometry><cylinder radius="1" length="0.1"/></geometry></collision>',
  );
  const { report } = sa.importUrdf(xml, { tip: 'iiwa_link_ee' });
  assert.ok(report.startContacts.length > 0);
  for (const c of report.startContacts) {
    assert.equal(c.links[1], 'iiwa_link_7');
    assert.equal(c.joints[1], 'iiwa_joint_7');
    assert.ok(c.distance < 0);
  }
});

test('joint vectors by name wherever q and q0 are; a wrong name is an Error naming it', () => {
  const robot = sa.robotFromUrdf(urdf('ur5_robot.urdf'), { tip: 'ee_link' });
  const q = [0.1, -0.5, 0.7, 0.2, -0.3, 0.4];
  const named = Object.fromEntries(robot.jointNames.map((n, k) => [n, q[k]]));
  assert.deepEqual(sa.forwardKinematics(robot, named), sa.forwardKinematics(robot, q));
  assert.deepEqual(sa.skeleton(robot, named), sa.skeleton(robot, q));
  const point = { link: 3, d: 0, a: 0.2 };
  assert.deepEqual(sa.controlPoint(robot, named, point), sa.controlPoint(robot, q, point));
  const scenario = { robot, obstacles: [], dt: 0.01, duration: 0.05 };
  assert.deepEqual(sa.simulate({ ...scenario, q0: named }), sa.simulate({ ...scenario, q0: q }));
  const w = new sa.World({ ...scenario, q0: named });
  assert.deepEqual([...w.q()], q);
  w.free();
  assert.throws(() => sa.skeleton(robot, { ...named, elbow: 1 }), /^Error: q\.elbow: no joint named "elbow" \(joints: shoulder_pan_joint, /);
  const { wrist_3_joint: _, ...short } = named;
  assert.throws(() => sa.forwardKinematics(robot, short), /^Error: q: missing joint "wrist_3_joint"$/);
  assert.throws(() => sa.simulate({ ...scenario, q0: { ...named, elbow: 1 } }), /^Error: q0\.elbow: no joint named "elbow"/);
  assert.throws(() => sa.simulate({ ...scenario, q0: { ...named, elbow_joint: 'x' } }), /^Error: q0\.elbow_joint: not a finite number$/);
  // A preset has no joint names: an array is needed.
  assert.throws(() => sa.skeleton('planar3', { a: 1 }), /^Error: q: joint values by name need a robot with jointNames/);
});
