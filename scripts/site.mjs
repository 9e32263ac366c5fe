// `npm run build`: the static site in dist/ — the playground page, the
// documentation page, the embedding example and the primitive gallery, on the
// npm package's own files — ready for any static host (every path is
// relative).
//
//   node scripts/site.mjs [--no-wasm]
//   (--no-wasm reuses crate/pkg and crate/pkg-node as they are)
//
// The package is built and packed first (scripts/package.mjs); its browser
// files are unpacked from the tarball into dist/skeleton-avoidance/ and the
// pages of web/ run on them (scripts/site-pages.mjs), so the site shows
// exactly what `npm install skeleton-avoidance` gives.
import fs from 'node:fs';
import path from 'node:path';
import zlib from 'node:zlib';
import { repo } from './lib.mjs';
import { ensureTools } from './tools.mjs';
import { buildPackage } from './package.mjs';
import { PACKAGE_DIR, unpackPackage, writePages } from './site-pages.mjs';
import { PRESET_MESHES } from '../web/preset-meshes.js';
import { copyEstimator } from './estimator-files.mjs';

/**
 * The size budget of the gzipped wasm, bytes (1.86 MB): 1.5 MB until the
 * mesh readers came in (mesh-loader for STL, OBJ, COLLADA and gltf for
 * glTF/GLB, about 120 and 95 kB gzipped on their own), 1.61 MB with them,
 * 1.72 MB with the articulated human, its keypoint tracks and the
 * constraints avoidance, 1.791 MB with the dynamics (the URDF and SRDF
 * readers built for size to make room: README), 1.834 MB with the robot's
 * own dynamics in the control step (torque mode, torque limits, ISO/TS
 * 15066 power and force limiting), NEO as a baseline controller and the
 * live sensor stream (pushHumanFrame, BlazePose's layout), 1.812 MB with
 * the cold crates (urdf-rs's regular expressions, parry, WebGL2's calls)
 * built for size, 1.852 MB with the planner (`planPath`: the certified
 * checker, RRT-Connect and its creeping search, the escape's QP and its
 * straightening, 2026-11-29). A budget against growth, not a goal: splitting the mesh
 * and URDF readers into a module loaded with the first URDF is the way
 * back under 1.5 MB.
 */
const LIMIT = 1_860_000;
/**
 * The size budget of dist/robots/ (bytes, uncompressed): the iiwa 14's, the
 * Panda's and the UR5's URDFs, collision meshes and licences, each robot's
 * fetched by the playground only when its preset is shown
 * (web/preset-meshes.js). 2.8 MB now, of which the iiwa's meshes are 2.3 MB
 * (0.94 MB gzipped, as a server sends them); the Panda's and the UR5's
 * together 0.45 MB.
 */
const ROBOTS_LIMIT = 3_000_000;
const web = path.join(repo, 'web');
const dist = path.join(repo, 'dist');

const build = !process.argv.includes('--no-wasm');
if (build && !ensureTools({ browser: false })) process.exit(1);
for (const dir of build ? [] : ['pkg', 'pkg-node']) {
  if (!fs.existsSync(path.join(repo, 'crate', dir, 'skeleton_avoidance_bg.wasm'))) {
    console.error(`site: crate/${dir} has no wasm; run without --no-wasm`);
    process.exit(1);
  }
}
const tarball = buildPackage({ build });
if (!tarball) process.exit(1);

fs.rmSync(dist, { recursive: true, force: true });
fs.mkdirSync(dist, { recursive: true });
let own;
try {
  unpackPackage(tarball, dist);
  own = writePages(dist, fs.readdirSync(web).filter((f) => f.endsWith('.html')));
} catch (err) {
  console.error(err instanceof Error ? err.message : err);
  process.exit(1);
}

const wasm = fs.readFileSync(path.join(dist, PACKAGE_DIR, 'web', 'skeleton_avoidance_bg.wasm'));
// Level 6, as `gzip -c` (and most servers) compress.
const gz = zlib.gzipSync(wasm, { level: 6 }).length;
const mb = (n) => (n / 1e6).toFixed(3);
console.log(`site: dist/ written: ${own.join(', ')} on ${PACKAGE_DIR}/ (from ${path.relative(repo, tarball)}); wasm ${mb(wasm.length)} MB, ${mb(gz)} MB gzipped (limit ${mb(LIMIT)} MB)`);
if (gz > LIMIT) {
  console.error('site: the wasm is over the size limit');
  process.exit(1);
}

// The presets' meshes, their URDFs, licences and the notes naming their
// sources (crate/tests/data), loaded lazily by the playground.
const data = path.join(repo, 'crate', 'tests', 'data');
const robotFiles = new Set(['meshes/README.md', 'urdf/README.md']);
for (const entry of Object.values(PRESET_MESHES)) {
  for (const f of [entry.urdf, ...entry.licences, ...entry.meshes]) robotFiles.add(f);
}
let robotBytes = 0;
for (const f of robotFiles) {
  const to = path.join(dist, 'robots', f);
  fs.mkdirSync(path.dirname(to), { recursive: true });
  fs.copyFileSync(path.join(data, f), to);
  robotBytes += fs.statSync(to).size;
}
console.log(`site: dist/robots/ ${robotFiles.size} files, ${mb(robotBytes)} MB (limit ${mb(ROBOTS_LIMIT)} MB; fetched only with the iiwa14, Panda or UR5 preset)`);
if (robotBytes > ROBOTS_LIMIT) {
  console.error('site: the preset meshes are over their size budget');
  process.exit(1);
}

// The camera's pose estimator (TensorFlow.js on wasm and MoveNet Lightning,
// from node_modules; scripts/estimator-files.mjs), fetched by the playground
// only when the camera is switched on: not part of the wasm budget above.
try {
  const bytes = copyEstimator(path.join(dist, 'estimator'));
  console.log(`site: dist/estimator/ ${mb(bytes)} MB (fetched only when the camera is switched on)`);
} catch (err) {
  console.error(err instanceof Error ? err.message : err);
  process.exit(1);
}
