// The pose estimator the playground's *Camera* loads (web/pose.js and
// web/pose-worker.js): TensorFlow.js on its wasm backend and MoveNet
// Lightning's weights, all from npm packages (devDependencies), served
// under `estimator/` by scripts/serve.mjs and copied to dist/estimator/ by
// scripts/site.mjs. Nothing of it is fetched before the camera is switched
// on, and nothing from anywhere but the page's own site.
//
// Name served → path under node_modules/ (or, for the notice, under the
// repository).
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');

export const ESTIMATOR_FILES = {
  // Apache-2.0 (Google); each file carries its licence header.
  'tf-core.min.js': '@tensorflow/tfjs-core/dist/tf-core.min.js',
  'tf-converter.min.js': '@tensorflow/tfjs-converter/dist/tf-converter.min.js',
  'tf-backend-wasm.min.js': '@tensorflow/tfjs-backend-wasm/dist/tf-backend-wasm.min.js',
  'tfjs-backend-wasm.wasm': '@tensorflow/tfjs-backend-wasm/dist/tfjs-backend-wasm.wasm',
  'tfjs-backend-wasm-simd.wasm': '@tensorflow/tfjs-backend-wasm/dist/tfjs-backend-wasm-simd.wasm',
  // MoveNet SinglePose Lightning as a TF.js graph model, from the Human
  // library's package (MIT, © Vladimir Mandic; the model is Google's, Apache-2.0).
  'movenet-lightning.json': '@vladmandic/human/models/movenet-lightning.json',
  'movenet-lightning.bin': '@vladmandic/human/models/movenet-lightning.bin',
  'LICENSE-human.txt': '@vladmandic/human/LICENSE',
};

/** Files of the repository served beside them. */
export const ESTIMATOR_OWN = { 'NOTICE.txt': 'scripts/estimator-notice.txt' };

/** The file on disk for served name `name` under `root` (a checkout), or null. */
export function estimatorFile(name, root = repo) {
  if (Object.hasOwn(ESTIMATOR_FILES, name)) return path.join(root, 'node_modules', ESTIMATOR_FILES[name]);
  if (Object.hasOwn(ESTIMATOR_OWN, name)) return path.join(root, ESTIMATOR_OWN[name]);
  return null;
}

/** Copies every estimator file into `dir`; returns the bytes copied. Throws naming a missing file. */
export function copyEstimator(dir, root = repo) {
  fs.mkdirSync(dir, { recursive: true });
  let bytes = 0;
  for (const name of [...Object.keys(ESTIMATOR_FILES), ...Object.keys(ESTIMATOR_OWN)]) {
    const from = estimatorFile(name, root);
    if (!fs.existsSync(from)) throw new Error(`estimator: ${path.relative(root, from)} is missing (npm ci installs it)`);
    fs.copyFileSync(from, path.join(dir, name));
    bytes += fs.statSync(from).size;
  }
  return bytes;
}
