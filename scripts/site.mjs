// `npm run build`: the static site in dist/ — the playground page, the
// documentation page, the embeddable element and the wasm package — ready
// for any static host (every path is relative).
//
//   node scripts/site.mjs [--no-wasm]
//   (--no-wasm reuses crate/pkg as it is)
import fs from 'node:fs';
import path from 'node:path';
import zlib from 'node:zlib';
import { repo } from './lib.mjs';
import { ensureTools } from './tools.mjs';
import { buildWasm } from './build.mjs';
import { PRESET_MESHES } from '../web/preset-meshes.js';

/**
 * The size budget of the gzipped wasm, bytes (1.8 MB): 1.5 MB until the
 * mesh readers came in (mesh-loader for STL, OBJ, COLLADA and gltf for
 * glTF/GLB, about 120 and 95 kB gzipped on their own), 1.61 MB with them,
 * 1.72 MB with the articulated human, its keypoint tracks and the
 * constraints avoidance. A budget against growth, not a goal: splitting
 * the mesh readers into a module loaded with the first URDF is the way
 * back under 1.5 MB.
 */
const LIMIT = 1_800_000;
/**
 * The size budget of dist/robots/ (bytes, uncompressed): the Panda's and the
 * UR5's URDFs, collision meshes and licences, fetched by the playground only
 * when one of those presets is shown (web/preset-meshes.js). 0.45 MB now.
 */
const ROBOTS_LIMIT = 600_000;
const web = path.join(repo, 'web');
const pkg = path.join(repo, 'crate', 'pkg');
const dist = path.join(repo, 'dist');

if (!process.argv.includes('--no-wasm')) {
  if (!ensureTools({ browser: false })) process.exit(1);
  if (buildWasm('web') !== 0) process.exit(1);
}
if (!fs.existsSync(path.join(pkg, 'skeleton_avoidance_bg.wasm'))) {
  console.error('site: crate/pkg has no wasm; run without --no-wasm');
  process.exit(1);
}

fs.rmSync(dist, { recursive: true, force: true });
fs.mkdirSync(path.join(dist, 'pkg'), { recursive: true });
for (const f of fs.readdirSync(web)) {
  if (/\.(html|js|css|json|svg|png)$/.test(f)) fs.copyFileSync(path.join(web, f), path.join(dist, f));
}
for (const f of ['skeleton_avoidance.js', 'skeleton_avoidance_bg.wasm', 'skeleton_avoidance.d.ts', 'package.json']) {
  if (fs.existsSync(path.join(pkg, f))) fs.copyFileSync(path.join(pkg, f), path.join(dist, 'pkg', f));
}
// The JS the module imports beside itself (the input boundary, wasm-bindgen's snippets/).
if (fs.existsSync(path.join(pkg, 'snippets'))) {
  fs.cpSync(path.join(pkg, 'snippets'), path.join(dist, 'pkg', 'snippets'), { recursive: true });
}

// The release build of crate/pkg is already shrunk by wasm-opt -Oz
// (scripts/build.mjs, cached by hash).
const wasmPath = path.join(dist, 'pkg', 'skeleton_avoidance_bg.wasm');
const wasm = fs.readFileSync(wasmPath);
// Level 6, as `gzip -c` (and most servers) compress.
const gz = zlib.gzipSync(wasm, { level: 6 }).length;
const mb = (n) => (n / 1e6).toFixed(3);
console.log(`site: dist/ written (${fs.readdirSync(dist).length} entries); wasm ${mb(wasm.length)} MB, ${mb(gz)} MB gzipped (limit ${mb(LIMIT)} MB)`);
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
console.log(`site: dist/robots/ ${robotFiles.size} files, ${mb(robotBytes)} MB (limit ${mb(ROBOTS_LIMIT)} MB; fetched only with the Panda or UR5 preset)`);
if (robotBytes > ROBOTS_LIMIT) {
  console.error('site: the preset meshes are over their size budget');
  process.exit(1);
}
