// The playground's pure helpers in Node: share links round-trip exactly and
// refuse damaged input with readable messages; shape edits keep shapes valid
// (moving and the reference point are the library's, as in the page).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createRequire } from 'node:module';
import { decodeShare, encodeShare, parseScenarioText } from '../../web/scenario-io.js';
import { defaultShape, rotateShape, scaleShape, shapeCenter, translateShape, useLibrary, PALETTE } from '../../web/playground.js';

const require = createRequire(import.meta.url);
const sa = require('../../crate/pkg-node/skeleton_avoidance.js');
useLibrary(sa);

const scenario = {
  robot: { preset: 'lwr4' },
  q0: [0.1, -0.7 / 3, Math.PI / 7, 1e-17, -2.5, 0.3333333333333333, 0],
  obstacles: [{ id: 'zoë «ball»', shape: { type: 'sphere', center: [0.1 + 0.2, -0.55, 1 / 3], radius: 0.05 } }],
  dt: 0.001,
  duration: 5,
};

test('a share link restores the scenario exactly (every double, unicode ids)', () => {
  const hash = `#${encodeShare(scenario)}`;
  assert.match(hash, /^#scenario=[A-Za-z0-9_-]+$/);
  assert.deepEqual(decodeShare(hash), scenario);
  assert.equal(decodeShare('#view=3d'), null, 'other fragments are not scenarios');
  assert.equal(decodeShare(''), null);
});

test('damaged links and files give readable messages', () => {
  assert.throws(() => decodeShare('#scenario=%%%'), /shared link is damaged/);
  assert.throws(() => decodeShare('#scenario=A'), /cannot be decoded|not valid JSON/);
  const cut = encodeShare(scenario).slice(0, 40);
  assert.throws(() => decodeShare(cut), /damaged|not valid JSON/);
  assert.throws(() => parseScenarioText('[1, 2]', 'The file "a.json"'), /The file "a.json" does not hold a scenario/);
  assert.throws(() => parseScenarioText('{"robot":', 'The file "b.json"'), /The file "b.json" is not valid JSON/);
});

test('shape edits: translate, scale and rotate about the centre', () => {
  const c = [0.4, -0.2, 0.3];
  for (const type of PALETTE) {
    const s = defaultShape(type, c, 0.9);
    assert.equal(s.type, type);
    const moved = translateShape(s, [0.1, 0, -0.05]);
    if (type !== 'plane' && type !== 'human') {
      const mc = shapeCenter(moved);
      const sc = shapeCenter(s);
      assert.ok(Math.abs(mc[0] - sc[0] - 0.1) < 1e-12 && Math.abs(mc[2] - sc[2] + 0.05) < 1e-12, `${type} moved`);
      const rotated = rotateShape(s, [0, 0, 1], 0.4);
      shapeCenter(rotated).forEach((x, k) => assert.ok(Math.abs(x - sc[k]) < 1e-12, `${type} rotates about its centre`));
      const bigger = scaleShape(s, 2);
      shapeCenter(bigger).forEach((x, k) => assert.ok(Math.abs(x - sc[k]) < 1e-12, `${type} scales about its centre`));
    }
  }
  const plane = defaultShape('plane', c, 1);
  const moved = translateShape(plane, [0.2, 0, 0]);
  // Points of the moved plane are the old ones moved.
  const on = (p, s) => s.normal.reduce((acc, n, k) => acc + n * p[k], 0) + s.offset;
  assert.ok(Math.abs(on(c, plane)) < 1e-12);
  assert.ok(Math.abs(on([c[0] + 0.2, c[1], c[2]], moved)) < 1e-12);
  // Every palette figure stays valid for the library after each edit.
  for (const type of PALETTE) {
    const s = defaultShape(type, c, 0.9);
    for (const edited of [translateShape(s, [0.1, 0.2, 0]), scaleShape(s, 1.25), rotateShape(s, [0, 0, 1], 0.3)]) {
      assert.equal(typeof sa.referencePoint(edited)[0], 'number', `${type} stays a valid figure`);
    }
  }
  const box = rotateShape(defaultShape('box', c, 1), [0, 0, 1], Math.PI / 2);
  const [x, y, z, w] = box.rotation;
  assert.ok(Math.abs(Math.hypot(x, y, z, w) - 1) < 1e-12 && Math.abs(z - Math.SQRT1_2) < 1e-12);
});
