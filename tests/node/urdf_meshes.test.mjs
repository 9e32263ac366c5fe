// The JS contract of `robotFromUrdf(xml, { meshes })` and
// `fitUrdf(xml, { tip?, base?, meshes })`, against the Node build at
// crate/pkg-node, on the UR5 URDF and its collision meshes (licences in
// crate/tests/data).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const sa = require('../../crate/pkg-node/skeleton_avoidance.js');
const data = (p) => new URL(`../../crate/tests/data/${p}`, import.meta.url);
const xml = fs.readFileSync(data('urdf/ur5_robot.urdf'), 'utf8');
const parts = ['base', 'shoulder', 'upperarm', 'forearm', 'wrist1', 'wrist2', 'wrist3'];
const meshes = () => Object.fromEntries(parts.map((p) =>
  [`ur5/collision/${p}.stl`, new Uint8Array(fs.readFileSync(data(`meshes/ur5/collision/${p}.stl`)))]));

test('fitUrdf: every collision vertex inside, before and after reported', () => {
  const fit = sa.fitUrdf(xml, { tip: 'ee_link', meshes: meshes() });
  assert.deepEqual(fit.problems, []);
  assert.equal(fit.after.robot.vertexCoverage, 1);
  assert.ok(fit.before.robot.vertexCoverage < 0.5, `${fit.before.robot.vertexCoverage}`);
  assert.equal(fit.after.bodies.length, 6);
  for (const b of fit.after.bodies) assert.equal(b.vertexCoverage, 1, b.name);
  // robotFromUrdf with the same meshes gives the same spec, usable everywhere.
  const robot = sa.robotFromUrdf(xml, { tip: 'ee_link', meshes: meshes() });
  assert.deepEqual(robot, fit.robot);
  const sk = sa.skeleton(robot, [0, -1, 1, 0, 1, 0]);
  assert.ok(sk.segments.every((s) => s.radius[0] > 0.03 && s.radius[1] > 0.03));
});

test('a missing mesh is named and the robot still loads; bad meshes input is refused by field', () => {
  const m = meshes();
  delete m['ur5/collision/forearm.stl'];
  m['ur5/collision/wrist2.stl'] = new Uint8Array([1, 2, 3]);
  const fit = sa.fitUrdf(xml, { tip: 'ee_link', meshes: m });
  assert.equal(fit.problems.length, 2);
  assert.match(fit.problems.join('\n'), /forearm\.stl/);
  assert.match(fit.problems.join('\n'), /wrist2\.stl/);
  assert.equal(fit.robot.joints.length, 6);
  assert.throws(() => sa.robotFromUrdf(xml, { meshes: { 'a.stl': 'text' } }),
    { message: /^options\.meshes: "a\.stl" is not a Uint8Array or an ArrayBuffer/ });
  assert.throws(() => sa.fitUrdf(xml, { meshes: 3 }), { message: /^options\.meshes: expected an object/ });
  assert.throws(() => sa.fitUrdf(xml, { tipp: 'x', meshes: {} }), { message: /^options\.tipp: unknown field/ });
});

test('a revoked proxy as the meshes is refused naming the field', () => {
  const { proxy, revoke } = Proxy.revocable({}, {});
  revoke();
  assert.throws(() => sa.fitUrdf(xml, { tip: 'ee_link', meshes: proxy }), /^Error: options\.meshes: could not be read/);
  assert.throws(() => sa.robotFromUrdf(xml, { meshes: proxy }), /^Error: options\.meshes/);
});
