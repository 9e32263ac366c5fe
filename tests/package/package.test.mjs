// The npm package as a user gets it: the tarball from `npm pack`
// (scripts/package.mjs, built by the `package` layer of `npm test`) installed
// into a fresh temporary project, a TypeScript file type-checked against its
// declarations with `tsc` (strict; a misuse must be a type error), compiled
// and run in Node.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { spawnSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';

const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..');
const npmDir = path.join(repo, 'target', 'npm');
const tsc = path.join(repo, 'node_modules', '.bin', 'tsc');

function sh(cmd, args, cwd) {
  const r = spawnSync(cmd, args, { cwd, encoding: 'utf8' });
  return { status: r.status, out: `${r.stdout ?? ''}${r.stderr ?? ''}` };
}

const MAIN_TS = `
import {
  robotFromUrdf, robotPreset, forwardKinematics, skeleton, distance, simulate, World,
  monteCarlo, monteCarloRuns, monteCarloMerge,
  type RobotSpec, type Primitive, type Scenario, type Trace, type WorldState, type MonteCarloReport,
} from 'skeleton-avoidance';

const xml = \`<robot name="two">
  <link name="base"/><link name="upper"><collision><geometry><cylinder radius="0.06" length="0.4"/></geometry></collision></link>
  <link name="fore"/><link name="tool"/>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="50" velocity="2"/></joint>
  <joint name="elbow" type="continuous"><parent link="upper"/><child link="fore"/>
    <origin xyz="0 0 0.4"/><axis xyz="0 1 0"/></joint>
  <joint name="flange" type="fixed"><parent link="fore"/><child link="tool"/><origin xyz="0 0 0.3"/></joint>
</robot>\`;

const robot: RobotSpec = robotFromUrdf(xml, { tip: 'tool' });
const names: string[] = robotFromUrdf(xml).jointNames;
const fk = forwardKinematics(robot, [0, 0]);
const tip = [fk.endEffector[0][3], fk.endEffector[1][3], fk.endEffector[2][3]];
const sk = skeleton(robot, new Float64Array([0.3, -0.4]));
const ball: Primitive = { type: 'sphere', center: [0.3, 0, 0.7], radius: 0.05 };
const d = distance(ball, { type: 'point', p: [0, 0, 0.7] }).distance;
const scenario: Scenario = {
  robot,
  q0: [0.2, 0.4],
  obstacles: [{ id: 'ball', shape: ball, motion: { type: 'linear', velocity: [-0.1, 0, 0] } }],
  dt: 0.001,
  duration: 0.05,
};
const trace: Trace = simulate(scenario);
const world = new World({ ...scenario, robot: robotPreset('planar3'), q0: [0.3, -0.5, 0.4] });
world.advance(0.001, 10);
const state: WorldState = world.state();
world.free();
const study: MonteCarloReport = monteCarlo(scenario, { runs: 2, seed: 1 });
const merged = monteCarloMerge(monteCarloRuns(scenario, { seed: 1, count: 2 }));

// Type errors tsc must report (never called: they would throw at run time).
export function misuses(): void {
  // @ts-expect-error: a sphere has a radius, not a size (the types are not \`any\`).
  distance({ type: 'sphere', center: [0, 0, 0], size: 1 }, ball);
  // @ts-expect-error: the options name links.
  robotFromUrdf(xml, { end: 'tool' });
  // @ts-expect-error: a scenario needs dt and duration.
  simulate({ robot, obstacles: [] });
  // @ts-expect-error: a study needs its number of runs.
  monteCarlo(scenario, { seed: 1 });
}

console.log(JSON.stringify({
  names, tip, segments: sk.segments.length, d, samples: trace.samples.length,
  t: state.t, radius: robot.joints[0].radius,
  studyRuns: study.runs, sameStudy: JSON.stringify(merged) === JSON.stringify(study),
}));
`;

// CommonJS: \`require\` through the package's index.cjs and index.d.cts.
const CJS_CTS = `
import sa = require('skeleton-avoidance');
const trace: sa.Trace = sa.simulate({ robot: { preset: 'planar3' }, obstacles: [], dt: 0.01, duration: 0.05 });
const world = new sa.World({ robot: { preset: 'planar3' }, obstacles: [], dt: 0.01, duration: 1 });
world.advance(0.01, 3);
let viewer = 'constructed';
try {
  new (sa.Viewer as unknown as new () => unknown)();
} catch (e) {
  viewer = (e as Error).message;
}
console.log(JSON.stringify({ samples: trace.samples.length, t: world.time, keys: Object.keys(sa).sort(), viewer }));
world.free();
`;

test('the packed package installs, type-checks with tsc and runs in Node', () => {
  const tarballs = fs.existsSync(npmDir) ? fs.readdirSync(npmDir).filter((f) => f.endsWith('.tgz')) : [];
  assert.equal(tarballs.length, 1, 'run `node scripts/package.mjs` first (the package layer of npm test does)');
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'skeleton-avoidance-package-'));
  try {
    fs.writeFileSync(path.join(dir, 'package.json'), JSON.stringify({ name: 'consumer', private: true, type: 'module' }));
    const install = sh('npm', ['install', '--no-audit', '--no-fund', '--offline', path.join(npmDir, tarballs[0])], dir);
    assert.equal(install.status, 0, install.out);
    fs.writeFileSync(path.join(dir, 'main.ts'), MAIN_TS);
    fs.writeFileSync(path.join(dir, 'cjs.cts'), CJS_CTS);
    fs.writeFileSync(path.join(dir, 'tsconfig.json'), JSON.stringify({
      compilerOptions: {
        target: 'es2022', module: 'nodenext', moduleResolution: 'nodenext', strict: true,
        noEmitOnError: true, skipLibCheck: false, types: [], outDir: 'out',
      },
      files: ['main.ts', 'cjs.cts'],
    }));
    const typed = sh(tsc, ['-p', '.'], dir);
    assert.equal(typed.status, 0, `tsc:\n${typed.out}`);
    const ran = sh(process.execPath, ['out/main.js'], dir);
    assert.equal(ran.status, 0, ran.out);
    const r = JSON.parse(ran.out.trim().split('\n').pop());
    assert.deepEqual(r.names, ['shoulder', 'elbow']);
    r.tip.forEach((v, i) => assert.ok(Math.abs(v - [0, 0, 1.0][i]) < 1e-12, `tip ${r.tip}`));
    assert.ok(r.segments >= 2);
    assert.ok(Math.abs(r.d - 0.25) < 1e-12);
    assert.ok(r.samples > 0);
    assert.ok(Math.abs(r.t - 0.01) < 1e-12);
    assert.equal(r.radius, 0.06);
    assert.equal(r.studyRuns, 2);
    assert.equal(r.sameStudy, true, 'monteCarloRuns + monteCarloMerge = monteCarlo');
    // require(): the same API from index.cjs; Viewer is a stand-in that rejects in Node.
    const cjs = sh(process.execPath, ['out/cjs.cjs'], dir);
    assert.equal(cjs.status, 0, cjs.out);
    const c = JSON.parse(cjs.out.trim().split('\n').pop());
    assert.ok(c.samples > 0);
    assert.ok(Math.abs(c.t - 0.03) < 1e-12, `World.time ${c.t}`);
    const esmKeys = sh(process.execPath, ['--input-type=module', '-e', "import * as sa from 'skeleton-avoidance'; console.log(JSON.stringify(Object.keys(sa).sort()))"], dir);
    assert.deepEqual(c.keys, JSON.parse(esmKeys.out.trim()), 'require and import give the same names');
    assert.ok(c.keys.includes('Viewer') && c.keys.includes('World'));
    // `skeleton-avoidance/compat` in Node is the Node entry (import and require).
    const compatKeys = sh(process.execPath, ['--input-type=module', '-e', "import * as sa from 'skeleton-avoidance/compat'; import { createRequire } from 'node:module'; const r = createRequire(import.meta.url)('skeleton-avoidance/compat'); console.log(JSON.stringify([Object.keys(sa).sort(), Object.keys(r).sort(), sa.simulate === r.simulate]))"], dir);
    assert.deepEqual(JSON.parse(compatKeys.out.trim()), [c.keys, c.keys, true], compatKeys.out);
    assert.match(c.viewer, /browser/, 'Viewer in Node says it needs a browser');
    // Benchmark helpers are not part of the package's API.
    const entry = fs.readFileSync(path.join(dir, 'node_modules', 'skeleton-avoidance', 'index.node.js'), 'utf8');
    assert.ok(!/bench/i.test(entry));
  } finally {
    fs.rmSync(dir, { recursive: true, force: true });
  }
});
