// A live person: the *Camera* (the browser's camera and a pose estimator in
// the page, web/pose.js, loaded only when it is switched on) and the
// *Sensor bridge* (web/bridge-client.js), both opt-in, feeding the scene's
// person through the `HumanFeed`; *Record* keeps the frames given as a
// keypoint track. A thumbnail over the view shows the camera with the
// detected skeleton; the HUD gets the end-to-end latency (capture → pose →
// step) and the estimator's rate.
//
// Owns: the panel's section, the thumbnail, the camera's stream and video,
// the estimator, the bridge client, the feed. Interface: `sim`,
// `messages`, `estimator` (the base URL of the estimator's files; no
// camera without it), `speed()`, `changed()`, `selected()` (the obstacle
// selected: a human there is the one driven).
import { errorText, h } from './dom.js';
import { HumanFeed } from './human-feed.js';
import { BridgeClient } from './bridge-client.js';
import { liftCoco17, metresPerPixel, placeInWorld, MIN_SCORE } from './keypoints.js';

const EDGES = [[5, 6], [5, 7], [7, 9], [6, 8], [8, 10], [5, 11], [6, 12], [11, 12], [11, 13], [13, 15], [12, 14], [14, 16], [0, 1], [0, 2], [1, 3], [2, 4]];

/** Why the camera could not start, in words (the error of getUserMedia or of the estimator). */
export function cameraProblem(err) {
  const name = err?.name ?? '';
  if (name === 'NotAllowedError' || name === 'SecurityError') return 'The camera was denied. Allow it in the browser\'s site settings to use it; the playground keeps running without it.';
  if (name === 'NotFoundError' || name === 'OverconstrainedError' || name === 'DevicesNotFoundError') return 'No camera was found on this machine; the playground keeps running without it.';
  if (name === 'NotReadableError') return 'The camera is in use by another program or could not be read.';
  return `The camera could not start: ${errorText(err)}`;
}

export class LiveInput {
  constructor(host) {
    this.host = host;
    this.feed = new HumanFeed({ sim: host.sim, messages: host.messages });
    this.bridge = new BridgeClient({ offer: (f) => this.feed.offer(f), notice: (t, p) => this.notice(t, p), closed: (t) => this.bridgeClosed(t) });
    this.estimator = null;
    this.stream = null;
    this.on = false;
    this.poseMs = NaN;
    this.scale = null;
    this.state = 'off';
    this.video = h('video', { muted: true, playsinline: true, autoplay: true });
    this.thumb = h('canvas', { class: 'camera-thumb', id: 'camera-thumb', width: 160, height: 120, hidden: true, 'aria-label': 'camera picture with the detected skeleton' });
    this.el = {};
  }

  /** The panel's section: the camera, the person's height, recording, the bridge. */
  section() {
    const el = this.el;
    el.camera = h('button', { type: 'button', id: 'camera', 'aria-pressed': 'false', onclick: () => (this.on ? this.stop() : this.start()),
      title: 'use this computer\'s camera: a pose estimator in the page drives the selected person (nothing leaves the machine)' }, 'Camera');
    el.height = h('input', { type: 'number', id: 'camera-height', min: '1', max: '2.3', step: '0.01', value: '1.70', title: 'the person\'s height (m): the scale of the camera\'s 2D keypoints' });
    el.record = h('button', { type: 'button', id: 'record', 'aria-pressed': 'false', onclick: () => this.toggleRecord(), title: 'keep the frames given to the person as a keypoint track' }, 'Record');
    el.bridgeOn = h('input', { type: 'checkbox', id: 'bridge-on', onchange: () => this.toggleBridge() });
    el.bridgeUrl = h('input', { type: 'text', id: 'bridge-url', value: 'ws://127.0.0.1:8765/', size: 18, 'aria-label': 'bridge address (this machine only)' });
    el.message = h('div', { class: 'hint', id: 'camera-message', role: 'status' });
    return [
      h('h3', {}, 'Live person'),
      h('div', { class: 'row' }, el.camera, h('label', {}, 'height (m) ', el.height), el.record),
      h('div', { class: 'row', title: 'keypoint frames from a sensor program on this machine (scripts/bridge.mjs)' },
        h('label', {}, el.bridgeOn, ' sensor bridge'), el.bridgeUrl),
      el.message,
    ];
  }

  /** A line in the section (`problem`: shown as a failure). */
  notice(text, problem = false) {
    if (!this.el.message) {
      this.host.messages.status(text);
      return;
    }
    this.el.message.textContent = text;
    this.el.message.className = problem ? 'message' : 'hint';
  }

  /** Switches the camera on: the stream first (its refusal is the common failure), then the estimator. */
  async start() {
    if (this.on) return;
    this.on = true;
    this.setState('starting');
    this.notice('Starting the camera…');
    try {
      if (!this.host.estimator) throw new Error('this page serves no pose estimator (the element\'s estimator attribute)');
      if (!navigator.mediaDevices?.getUserMedia) throw Object.assign(new Error('this browser gives the page no camera (it needs https or localhost)'), { name: 'NotFoundError' });
      this.stream = await navigator.mediaDevices.getUserMedia({ video: { width: { ideal: 640 }, height: { ideal: 480 } }, audio: false });
      this.video.srcObject = this.stream;
      await this.video.play();
    } catch (err) {
      this.stop(cameraProblem(err));
      return;
    }
    try {
      this.notice('Loading the pose estimator (about 6 MB, once)…');
      const { PoseEstimator } = await import('./pose.js');
      this.estimator = await PoseEstimator.start(this.host.estimator);
    } catch (err) {
      this.stop(`The pose estimator could not start (${errorText(err)}); the playground keeps running without the camera.`);
      return;
    }
    if (!this.on) return;
    this.thumb.hidden = false;
    this.setState('running');
    this.notice(`Camera on: MoveNet Lightning on TensorFlow.js (${this.estimator.info.backend}), loaded in ${this.estimator.info.loadMs.toFixed(0)} ms. Drag the person to place them.`);
    this.run();
  }

  /**
   * Estimates frame after frame while the camera is on. At most two
   * frames are with the estimator (one running, the next waiting in its
   * worker, so that it never idles while this thread draws): never a
   * queue. A frame is taken only when the camera has shown a new one; the
   * frames' capture times come from a watch of the video.
   */
  async run() {
    const estimator = this.estimator;
    const live = () => this.on && this.estimator === estimator;
    const frames = watchFrames(this.video, live);
    this.frameWatch = frames;
    const inflight = [];
    let done = -1;
    while (live()) {
      while (inflight.length < 2 && frames.count !== done) {
        done = frames.count;
        const capturedAt = frames.at;
        const answer = estimator.estimate(this.video).then((pose) => ({ pose, capturedAt }));
        answer.catch(() => {});
        inflight.push(answer);
      }
      if (inflight.length === 0) {
        await frames.next();
        continue;
      }
      let result;
      try {
        result = await inflight.shift();
      } catch (err) {
        if (live()) this.stop(`The pose estimator stopped: ${errorText(err)}`);
        return;
      }
      if (!live()) return;
      this.poseMs = result.pose.ms;
      this.lastPose = result.pose;
      this.drawThumb(result.pose);
      this.offerPose(result.pose, result.capturedAt);
    }
  }

  /** A pose as a frame for the feed: lifted to metres by the height, placed by the feed. */
  offerPose(pose, capturedAt) {
    const height = Math.min(2.3, Math.max(1, Number(this.el.height?.value) || 1.7));
    const measured = metresPerPixel(pose.points, pose.scores, height);
    if (measured === null) return;
    // The scale is smoothed: it is the noisiest figure of the lift.
    this.scale = this.scale === null ? measured : 0.7 * this.scale + 0.3 * measured;
    const body = liftCoco17(pose.points, pose.scores, height, this.scale);
    if (!body) return;
    this.feed.offer({ layout: 'coco17', keypoints: body.keypoints, confidence: body.confidence, capturedAt, source: 'camera' });
  }

  /** Called by the frame loop before its steps: the latest frame into the world. */
  apply() {
    const frame = this.feed.pending;
    if (!frame) return;
    // The selected person is the one driven (else the one driven so far, else the first).
    const selected = this.host.selected?.();
    if (selected && selected !== this.feed.id && this.host.sim.shapeOf(selected)?.type === 'human') this.feed.follow(selected);
    const place = frame.source === 'camera' ? (points, anchor) => placeInWorld(points, anchor) : (points) => points;
    if (this.feed.apply(place, this.host.speed())) this.host.changed();
  }

  stop(problem) {
    this.on = false;
    // A loop waiting for a frame that will not come ends.
    for (const resolve of this.frameWatch?.waiting.splice(0) ?? []) resolve();
    this.estimator?.stop();
    this.estimator = null;
    for (const track of this.stream?.getTracks() ?? []) track.stop();
    this.stream = null;
    this.video.srcObject = null;
    this.thumb.hidden = true;
    this.scale = null;
    this.setState(problem ? 'failed' : 'off');
    this.notice(problem ?? 'Camera off.', Boolean(problem));
  }

  setState(state) {
    this.state = state;
    if (!this.el.camera) return;
    this.el.camera.setAttribute('aria-pressed', String(state === 'running' || state === 'starting'));
    this.el.camera.textContent = state === 'running' ? 'Camera on' : state === 'starting' ? 'Camera…' : 'Camera';
  }

  toggleRecord() {
    const on = !this.feed.recording;
    if (on) {
      this.feed.record(true);
      this.notice('Recording the frames given to the person…');
    } else {
      this.feed.record(false);
      const json = this.feed.recorder.json();
      if (json) download(json, 'live-track.json');
      this.notice(json ? `Saved ${this.feed.recorder.frames.length} frames as live-track.json (open it as a keypoint track to replay).` : 'Nothing was recorded.');
    }
    this.el.record?.setAttribute('aria-pressed', String(on));
  }

  toggleBridge() {
    if (!this.el.bridgeOn.checked) {
      this.bridge.close();
      this.notice('Bridge off.');
      return;
    }
    try {
      this.bridge.connect(this.el.bridgeUrl.value);
    } catch (err) {
      this.el.bridgeOn.checked = false;
      this.notice(errorText(err), true);
    }
  }

  bridgeClosed(text) {
    if (this.el.bridgeOn) this.el.bridgeOn.checked = false;
    this.notice(text);
  }

  /** Lines for the HUD while a live source runs: latency and rates. */
  hudLines() {
    if (this.state !== 'running' && !this.bridge.open) return [];
    const f = this.feed;
    const latency = Number.isFinite(f.latencyMs) ? `${f.latencyMs.toFixed(0)} ms` : '—';
    const source = this.state === 'running' ? `camera: pose ${f.rate.toFixed(1)} Hz (model ${this.poseMs.toFixed(0)} ms)` : `bridge: ${f.rate.toFixed(1)} Hz`;
    return [`${source}  latency ${latency}`];
  }

  /** The thumbnail: the camera's picture and the skeleton found in it. */
  drawThumb(pose) {
    const c = this.thumb.getContext('2d');
    const w = this.video.videoWidth;
    const hgt = this.video.videoHeight;
    if (!c || !(w > 0)) return;
    const k = Math.min(this.thumb.width / w, this.thumb.height / hgt);
    const ox = (this.thumb.width - w * k) / 2;
    const oy = (this.thumb.height - hgt * k) / 2;
    c.fillStyle = '#000';
    c.fillRect(0, 0, this.thumb.width, this.thumb.height);
    c.drawImage(this.video, ox, oy, w * k, hgt * k);
    const at = (p) => [ox + p[0] * k, oy + p[1] * k];
    c.lineWidth = 2;
    c.strokeStyle = '#ff3d7f';
    for (const [a, b] of EDGES) {
      if (pose.scores[a] < MIN_SCORE || pose.scores[b] < MIN_SCORE) continue;
      c.beginPath();
      c.moveTo(...at(pose.points[a]));
      c.lineTo(...at(pose.points[b]));
      c.stroke();
    }
    c.fillStyle = '#ffe14d';
    pose.points.forEach((p, i) => {
      if (pose.scores[i] < MIN_SCORE) return;
      const [x, y] = at(p);
      c.fillRect(x - 2, y - 2, 4, 4);
    });
  }
}

/**
 * Watches `video`'s frames while `alive()`: `count` of frames shown, `at`
 * the page's time (ms) the latest was captured (the camera's own capture
 * time where the browser gives it, else when it was shown), `next()`
 * resolves at the next frame.
 */
function watchFrames(video, alive) {
  const w = { count: 0, at: performance.now(), waiting: [] };
  w.next = () => new Promise((resolve) => w.waiting.push(resolve));
  const seen = (meta) => {
    const now = performance.now();
    w.at = Number.isFinite(meta?.captureTime) && meta.captureTime <= now ? meta.captureTime : now;
    w.count += 1;
    for (const resolve of w.waiting.splice(0)) resolve();
  };
  const rvfc = typeof video.requestVideoFrameCallback === 'function';
  const watch = () => {
    if (!alive()) {
      for (const resolve of w.waiting.splice(0)) resolve();
      return;
    }
    if (rvfc) video.requestVideoFrameCallback((_, meta) => { seen(meta); watch(); });
    else requestAnimationFrame(() => { seen(null); watch(); });
  };
  watch();
  return w;
}

function download(text, name) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(new Blob([text], { type: 'application/json' }));
  a.download = name;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}
