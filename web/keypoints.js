// Keypoint frames for a live person: a pose estimator's 2D COCO-17 keypoints
// lifted to metres by the person's height and placed in the robot's frame;
// the check of a frame that arrives from outside (the sensor bridge); the
// recording of the frames given to the world as a keypoint track.
//
// No state and no page: plain functions, tested in Node
// (tests/node/camera-keypoints.test.mjs).

/** The layouts a frame may name, with their keypoint counts (the library's). */
export const LAYOUTS = { coco17: 17, body25: 25, kinect32: 32, blazepose33: 33 };

/** At most this many keypoints in a frame (the library's bound too). */
export const MAX_KEYPOINTS = 10_000;

/** A keypoint scored below this is not taken as seen (MoveNet's own cut-off). */
export const MIN_SCORE = 0.3;

/** The library's confidence at and above which a keypoint is good (`GOOD_CONFIDENCE` in crate/src/world/stream.rs). */
export const GOOD_CONFIDENCE = 0.5;

/**
 * An estimator's score as the library's confidence: the estimator's cut-off
 * `MIN_SCORE` is mapped onto the library's `GOOD_CONFIDENCE`, linearly on
 * either side (0 → 0, 1 → 1), so that a keypoint is good for the world
 * exactly when the estimator counts it as seen. Without it a wrist MoveNet
 * sees at 0.46 would be held at its last good place by the world while the
 * page draws it where it is.
 */
export function calibrated(score) {
  const s = Math.min(1, Math.max(0, score));
  return s < MIN_SCORE
    ? (GOOD_CONFIDENCE * s) / MIN_SCORE
    : GOOD_CONFIDENCE + ((1 - GOOD_CONFIDENCE) * (s - MIN_SCORE)) / (1 - MIN_SCORE);
}

// COCO-17 indices.
const SHOULDER = [5, 6];
const ELBOW = [7, 8];
const WRIST = [9, 10];
const HIP = [11, 12];
const KNEE = [13, 14];
const ANKLE = [15, 16];

// Body proportions as fractions of the standing height (anthropometric
// tables, rounded): the hip joints' height, the torso (mid shoulders to mid
// hips), the distance between the shoulder keypoints, the upper arm, the
// forearm, the thigh, the shin, the ankle's height, the nose above the
// shoulders.
export const PROPORTIONS = { hip: 0.51, torso: 0.288, shoulders: 0.22, upperArm: 0.186, forearm: 0.146, thigh: 0.245, shin: 0.246, ankle: 0.039, nose: 0.13 };

const mid = (a, b) => [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2];
const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1]);

/**
 * Metres per pixel of a 2D COCO-17 pose for a person `height` m tall: from
 * the torso when both shoulders and hips are seen, else from the shoulders;
 * null when neither is seen (no person to place).
 */
export function metresPerPixel(points, scores, height) {
  const seen = (list) => list.every((k) => scores[k] >= MIN_SCORE);
  if (seen([...SHOULDER, ...HIP])) {
    const torso = dist(mid(points[5], points[6]), mid(points[11], points[12]));
    if (torso > 1) return (PROPORTIONS.torso * height) / torso;
  }
  if (seen(SHOULDER)) {
    const width = dist(points[5], points[6]);
    if (width > 1) return (PROPORTIONS.shoulders * height) / width;
  }
  return null;
}

/**
 * A 2D COCO-17 pose (`points` in image pixels, y down; `scores` 0–1) as
 * 3-D keypoints in the person's own frame: `[lateral, forward, up]` in
 * metres, lateral towards the person's left (the image's right: the camera
 * faces the person), forward towards the camera, up from the floor under
 * the middle of the hips. The image is taken as the plane of the body; an
 * arm shorter in the image than its length is leaned forward by the
 * difference. Keypoints not seen are put where a person standing with the
 * arms down has them (legs below the hips, arms hanging), with their low
 * score kept as the confidence (see `calibrated`). `scale` (m/px) may be given (smoothed by
 * the caller); else it is measured. Null when no person is seen.
 */
export function liftCoco17(points, scores, height, scale = metresPerPixel(points, scores, height)) {
  if (scale === null || !(scale > 0)) return null;
  const P = PROPORTIONS;
  const seen = (k) => scores[k] >= MIN_SCORE;
  const hips = seen(HIP[0]) && seen(HIP[1]) ? mid(points[11], points[12]) : null;
  const shoulders = mid(points[5], points[6]);
  // The hips' point in the image: seen, or below the shoulders by the torso.
  const origin = hips ?? [shoulders[0], shoulders[1] + (P.torso * height) / scale];
  const at = (k) => [(points[k][0] - origin[0]) * scale, 0, P.hip * height + (origin[1] - points[k][1]) * scale];
  const out = points.map((_, k) => at(k));
  const below = (p, drop) => [p[0], p[1], p[2] - drop];
  for (let side = 0; side < 2; side++) {
    const [s, e, w, hp, kn, an] = [SHOULDER[side], ELBOW[side], WRIST[side], HIP[side], KNEE[side], ANKLE[side]];
    if (!seen(hp)) out[hp] = [(side === 0 ? 0.05 : -0.05) * height, 0, P.hip * height];
    if (!seen(kn)) out[kn] = below(out[hp], P.thigh * height);
    if (!seen(an)) out[an] = [out[kn][0], out[kn][1], P.ankle * height];
    if (!seen(e)) out[e] = below(out[s], P.upperArm * height);
    else out[e][1] = lean(out[s], out[e], P.upperArm * height);
    if (!seen(w)) out[w] = below(out[e], P.forearm * height);
    else out[w][1] = out[e][1] + lean(out[e], out[w], P.forearm * height);
  }
  // The head's keypoints (nose, eyes, ears) not seen: above the shoulders.
  for (let k = 0; k < 5; k++) {
    if (!seen(k)) out[k] = [(out[5][0] + out[6][0]) / 2, 0, (out[5][2] + out[6][2]) / 2 + P.nose * height];
  }
  return { keypoints: out, confidence: scores.map(calibrated) };
}

/** How far forward (m) a limb of `length` seen from `a` to `b` in the body's plane leans. */
function lean(a, b, length) {
  const seenLength = Math.hypot(b[0] - a[0], b[2] - a[2]);
  return Math.sqrt(Math.max(0, length * length - seenLength * seenLength));
}

/**
 * The person's frame placed in the world: `anchor` the floor point under the
 * hips, the person facing `towards` (the robot's base) horizontally.
 */
export function placeInWorld(bodyPoints, anchor, towards = [0, 0, 0]) {
  let ux = towards[0] - anchor[0];
  let uy = towards[1] - anchor[1];
  const n = Math.hypot(ux, uy);
  if (n < 1e-9) { ux = -1; uy = 0; } else { ux /= n; uy /= n; }
  // The person's left when facing u (z × u).
  const lx = -uy;
  const ly = ux;
  return bodyPoints.map(([l, f, z]) => [anchor[0] + lx * l + ux * f, anchor[1] + ly * l + uy * f, anchor[2] + z]);
}

/**
 * A frame from outside (one JSON line of the sensor bridge), checked:
 * `{ t, layout, keypoints: [[x, y, z], …], confidence?, obstacle? }`, metres
 * in the world frame. Returns the frame (copied) or throws an Error naming
 * the field.
 */
export function checkFrame(value) {
  if (value === null || typeof value !== 'object' || Array.isArray(value)) throw new Error('frame: expected an object');
  const { t, layout, keypoints, confidence, obstacle } = value;
  if (typeof t !== 'number' || !Number.isFinite(t)) throw new Error('t: not a finite number');
  if (!Object.hasOwn(LAYOUTS, layout)) throw new Error(`layout: unknown layout (expected ${Object.keys(LAYOUTS).join(', ')})`);
  if (!Array.isArray(keypoints)) throw new Error('keypoints: expected an array');
  if (keypoints.length > MAX_KEYPOINTS) throw new Error(`keypoints: more than ${MAX_KEYPOINTS}`);
  if (keypoints.length !== LAYOUTS[layout]) throw new Error(`keypoints: ${layout} has ${LAYOUTS[layout]} keypoints, got ${keypoints.length}`);
  const points = keypoints.map((p, k) => {
    if (!Array.isArray(p) || p.length !== 3 || !p.every((v) => typeof v === 'number' && Number.isFinite(v))) {
      throw new Error(`keypoints[${k}]: expected three finite numbers`);
    }
    return [p[0], p[1], p[2]];
  });
  const frame = { t, layout, keypoints: points };
  if (confidence !== undefined) {
    if (!Array.isArray(confidence) || confidence.length !== points.length) throw new Error('confidence: expected one number per keypoint');
    confidence.forEach((c, k) => {
      if (typeof c !== 'number' || !(c >= 0 && c <= 1)) throw new Error(`confidence[${k}]: expected a number in [0, 1]`);
    });
    frame.confidence = confidence.slice();
  }
  if (obstacle !== undefined) {
    if (typeof obstacle !== 'string' || obstacle.length === 0 || obstacle.length > 200) throw new Error('obstacle: expected an obstacle id');
    frame.obstacle = obstacle;
  }
  return frame;
}

/**
 * The frames given to the world, kept as a keypoint track (the library's
 * JSON track format: `{ layout, frames: [{ t, keypoints }] }`); at most
 * `limit` frames (the library's cap on keyframes), the oldest dropped.
 */
export class TrackRecorder {
  constructor(limit = 100_000) {
    this.limit = limit;
    this.frames = [];
    this.layout = null;
  }

  /** Keeps `frame` (a frame as given to the world); a frame of another layout starts a new track. */
  add(frame) {
    if (this.layout !== frame.layout) this.frames = [];
    this.layout = frame.layout;
    const last = this.frames[this.frames.length - 1];
    if (last && !(frame.t > last.t)) return;
    this.frames.push({ t: frame.t, keypoints: frame.keypoints.map((p) => p.slice()) });
    if (this.frames.length > this.limit) this.frames.shift();
  }

  /** The track as JSON text (null while empty). Numbers round-trip exactly. */
  json() {
    return this.frames.length ? JSON.stringify({ layout: this.layout, frames: this.frames }) : null;
  }

  clear() {
    this.frames = [];
    this.layout = null;
  }
}
