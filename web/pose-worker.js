// The pose estimator's worker (a classic worker: TensorFlow.js's scripts are
// loaded with importScripts from the site's `estimator/` folder): MoveNet
// SinglePose Lightning on TensorFlow.js's wasm backend. Started by
// web/pose.js when the camera is switched on; it receives 192×192 RGBA
// pixels (the camera's frame letterboxed to a square) and answers the 17
// COCO keypoints, normalised to that square, with their scores.
//
// Messages in: { type: 'init', base } then { type: 'frame', id, pixels }.
// Messages out: { type: 'ready', backend, loadMs } or { type: 'error', message },
// { type: 'pose', id, points: [[x, y], …] (0–1), scores, ms }.
/* global tf, importScripts */
'use strict';

const SIZE = 192;
let model = null;

async function init(base) {
  const t0 = performance.now();
  importScripts(`${base}tf-core.min.js`, `${base}tf-converter.min.js`, `${base}tf-backend-wasm.min.js`);
  tf.wasm.setWasmPaths(base);
  if (!(await tf.setBackend('wasm'))) throw new Error('TensorFlow.js could not start its wasm backend');
  await tf.ready();
  // TF.js reads whatever body a failed request returns: ask first, to say which file is missing.
  for (const name of ['movenet-lightning.json', 'movenet-lightning.bin']) {
    const answer = await fetch(`${base}${name}`, { method: 'HEAD' });
    if (!answer.ok) throw new Error(`the model's file ${name} could not be fetched (HTTP ${answer.status})`);
  }
  model = await tf.loadGraphModel(`${base}movenet-lightning.json`);
  // One run on a blank frame: the first is the slow one.
  const warm = model.execute(tf.zeros([1, SIZE, SIZE, 3], 'int32'));
  await warm.data();
  warm.dispose();
  return { backend: tf.getBackend(), loadMs: performance.now() - t0 };
}

async function estimate(pixels) {
  const t0 = performance.now();
  const rgb = new Int32Array(SIZE * SIZE * 3);
  for (let i = 0, j = 0; i < rgb.length; i += 3, j += 4) {
    rgb[i] = pixels[j];
    rgb[i + 1] = pixels[j + 1];
    rgb[i + 2] = pixels[j + 2];
  }
  const input = tf.tensor(rgb, [1, SIZE, SIZE, 3], 'int32');
  const output = model.execute(input);
  const values = await output.data();
  input.dispose();
  output.dispose();
  // [1, 1, 17, 3]: y, x, score.
  const points = [];
  const scores = [];
  for (let k = 0; k < 17; k++) {
    points.push([values[3 * k + 1], values[3 * k]]);
    scores.push(values[3 * k + 2]);
  }
  return { points, scores, ms: performance.now() - t0 };
}

self.onmessage = async (e) => {
  const msg = e.data;
  try {
    if (msg.type === 'init') {
      self.postMessage({ type: 'ready', ...(await init(msg.base)) });
    } else if (msg.type === 'frame' && model) {
      self.postMessage({ type: 'pose', id: msg.id, ...(await estimate(msg.pixels)) });
    }
  } catch (err) {
    self.postMessage({ type: 'error', id: msg.id, message: err instanceof Error ? err.message : String(err) });
  }
};
