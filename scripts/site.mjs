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
