// The arm as a rigid body in the World's JS contract, against crate/pkg-node:
// torque mode on the robot's own dynamics, the drive torques and effective
// masses in state(), the protective mode `pfl` and its readout, and the
// refusals of a robot without inertial data.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const sa = require('../../crate/pkg-node/skeleton_avoidance.js');

test('state() reports the drive torques, each control point\'s effective mass and the bound in force', () => {
  const w = new sa.World(sa.exampleScenario('human-reach'));
  w.setController({ protective: { mode: 'pfl' } });
  assert.equal(w.controller().protective.mode, 'pfl');
  w.advance(0.002, 700);
  const s = w.state();
  assert.equal(s.torque.length, 7);
  const limits = sa.robotPreset('panda').joints.map((j) => j.maxTorque);
  s.torque.forEach((t, i) => assert.ok(Math.abs(t) <= limits[i], `joint ${i}: ${t}`));
  assert.ok(s.controlPoints.length > 0);
  const masses = s.controlPoints.map((cp) => cp.effectiveMass).filter((m) => m !== undefined);
  assert.ok(masses.length > 0);
  for (const m of masses) assert.ok(m > 0 && m < 1e3, String(m));
  assert.ok(s.protection, 'the person is within reach');
  assert.match(s.protection.part, /^person:/);
  assert.ok(['ssm', 'pfl'].includes(s.protection.active));
  assert.equal(typeof s.protection.region, 'string');
  w.free();
});

test('torque mode runs on the robot\'s own dynamics within its torque limits', () => {
  const s = sa.exampleScenario('lwr4-elbow');
  s.controller.mode = 'torque';
  s.duration = 1;
  s.sampleEvery = 1;
  const trace = sa.simulate(s);
  assert.ok(trace.samples.every((x) => x.q.every(Number.isFinite)));
});

test('a robot without inertial data refuses torque mode and pfl, naming the links', () => {
  const w = new sa.World(sa.exampleScenario('planar-transition'));
  const before = w.controller();
  assert.throws(() => w.setController({ mode: 'torque' }), /^Error: controller\.mode: torque mode needs the robot's inertial data \(inertials: no inertial data for links .+\)$/);
  assert.throws(() => w.setController({ protective: { mode: 'pfl' } }), /^Error: controller\.protective\.mode: power and force limiting needs the robot's inertial data/);
  assert.throws(() => w.setController({ protective: { mode: 'fast' } }), /controller\.protective\.mode: unknown value "fast" \(known: ssm, pfl\)/);
  assert.deepEqual(w.controller(), before, 'a refused edit leaves the world unchanged');
  assert.equal(w.state().torque.length, 0);
  const s = sa.exampleScenario('planar-transition');
  s.controller.mode = 'torque';
  assert.throws(() => sa.simulate(s), /controller\.mode: torque mode needs the robot's inertial data/);
  w.free();
});
