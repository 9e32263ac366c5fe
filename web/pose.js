// The pose estimator in the page, loaded (a dynamic import) only when the
// camera is switched on: a worker runs MoveNet Lightning on TensorFlow.js's
// wasm backend (web/pose-worker.js), so the frame loop keeps its thread.
// Each camera frame is letterboxed to a 192×192 square here (padded, never
// squashed: tests/data/camera/ESTIMATOR.md) and its pixels go to the worker;
// the keypoints come back in the video's pixels.
//
// Everything is fetched from `base` (the site's `estimator/` folder; the
// files and their licences: scripts/estimator-files.mjs). No image leaves
// the page: the pixels go to the worker and nowhere else.

const SIZE = 192;

export class PoseEstimator {
  /** Starts the worker and loads the model; resolves once it has estimated a blank frame. */
  static async start(base) {
    const estimator = new PoseEstimator();
    await estimator.init(new URL(base, document.baseURI).href);
    return estimator;
  }

  constructor() {
    this.worker = new Worker(new URL('./pose-worker.js', import.meta.url));
    this.canvas = new OffscreenCanvas(SIZE, SIZE);
    this.context = this.canvas.getContext('2d', { willReadFrequently: true });
    this.waiting = new Map();
    this.nextId = 1;
    this.failed = null;
    this.info = null;
  }

  init(base) {
    return new Promise((resolve, reject) => {
      this.worker.onerror = (e) => {
        e.preventDefault?.();
        this.fail(new Error(`the estimator's worker failed: ${e.message || 'could not load'}`), reject);
      };
      this.worker.onmessage = (e) => {
        const msg = e.data;
        if (msg.type === 'ready') {
          this.info = { backend: msg.backend, loadMs: msg.loadMs };
          resolve();
        } else if (msg.type === 'error' && msg.id === undefined) {
          this.fail(new Error(msg.message), reject);
        } else {
          const pending = this.waiting.get(msg.id);
          this.waiting.delete(msg.id);
          if (!pending) return;
          if (msg.type === 'pose') pending.resolve(msg);
          else pending.reject(new Error(msg.message));
        }
      };
      this.worker.postMessage({ type: 'init', base });
    });
  }

  fail(err, reject) {
    this.failed = err;
    reject(err);
    for (const p of this.waiting.values()) p.reject(err);
    this.waiting.clear();
  }

  /**
   * The pose in `video`'s current frame: `{ points: [[x, y], …] (video
   * pixels), scores, ms }` (17 COCO keypoints; `ms` the model's time).
   */
  async estimate(video) {
    if (this.failed) throw this.failed;
    const w = video.videoWidth;
    const h = video.videoHeight;
    if (!(w > 0 && h > 0)) throw new Error('the camera gives no picture yet');
    const side = Math.max(w, h);
    const ox = (side - w) / 2;
    const oy = (side - h) / 2;
    const k = SIZE / side;
    this.context.fillStyle = '#000';
    this.context.fillRect(0, 0, SIZE, SIZE);
    this.context.drawImage(video, ox * k, oy * k, w * k, h * k);
    const pixels = this.context.getImageData(0, 0, SIZE, SIZE).data;
    const id = this.nextId++;
    const answer = await new Promise((resolve, reject) => {
      this.waiting.set(id, { resolve, reject });
      this.worker.postMessage({ type: 'frame', id, pixels }, [pixels.buffer]);
    });
    const points = answer.points.map(([x, y]) => [x * side - ox, y * side - oy]);
    return { points, scores: answer.scores, ms: answer.ms };
  }

  stop() {
    this.worker.terminate();
    this.failed = new Error('the estimator was stopped');
  }
}
