// Pointer, wheel, touch and keyboard input of the widget's view.
//
// An embedded widget must not trap the page: the wheel zooms only with
// Ctrl/⌘ held or once the view was clicked (until it loses focus), a hint
// says so otherwise; on touch screens vertical swipes scroll the page
// (`touch-action: pan-y`), horizontal drags orbit, two fingers pinch-zoom
// and pan. A double click (or F) frames the scene.
//
// Owns nothing lasting (a drag or a pinch in progress). Interface, given by
// the Playground (`InputHost` below): the canvas and the element whose keys
// it handles, the viewer, picking, the edits and pinning parts, messages,
// the wheel's engagement and the commands the keys run.
import { PALETTE, add, dot, len, moveHumanHand, mul, rotateShape, scaleShape, sub, translateShape } from './shapes.js';


/** Canvas pixel (drawing buffer) of a pointer event. */
function pixel(canvas, e) {
  const r = canvas.getBoundingClientRect();
  const dpr = window.devicePixelRatio || 1;
  return [(e.clientX - r.left) * dpr, (e.clientY - r.top) * dpr];
}

/** Where the ray through pixel `px` meets the plane through `p0` with normal `n`. */
function onPlane(viewer, px, p0, n) {
  const ray = viewer.rayAt(px[0], px[1]);
  const denom = dot(ray.direction, n);
  if (Math.abs(denom) < 1e-9) return null;
  const s = dot(sub(p0, ray.origin), n) / denom;
  return add(ray.origin, mul(ray.direction, s));
}

/** A drag that starts on an obstacle: it moves on the plane facing the camera. */
function obstacleDrag(pg, px, hit, e) {
  const viewer = pg.viewer();
  const n = viewer.viewDirection();
  // Metres per pixel at the picked point, for moves along the normal.
  const a = onPlane(viewer, px, hit.point, n);
  const b = onPlane(viewer, [px[0], px[1] + 1], hit.point, n);
  return { kind: 'obstacle', id: hit.id, shape: pg.shapeOf(hit.id), point: a ?? hit.point, n,
    y: px[1], mpp: a && b ? len(sub(a, b)) : 0.002, moved: false, along: e.altKey };
}

/** The hand a pick on a human's hand or forearm grabs (`left` / `right`), if any. */
function grabbedHand(hit) {
  const m = /^(left|right)(Hand|Forearm)$/.exec(hit.part ?? '');
  return m ? m[1] : null;
}

function moveObstacle(pg, drag, e) {
  const px = pixel(pg.canvas, e);
  if (drag.hand) {
    // A hand follows the pointer on the plane facing the camera; only its
    // arm moves (the library solves the arm), the rest of the body stays.
    const p = onPlane(pg.viewer(), px, drag.start, drag.n);
    if (!p) return true;
    const moved = pg.messages.guard(() => moveHumanHand(drag.shape, drag.hand, sub(p, drag.start)));
    if (!moved) return true;
    drag.moved = true;
    return pg.edits.setShape(drag.id, moved);
  }
  let delta;
  if (e.altKey || e.ctrlKey || e.metaKey) {
    delta = mul(drag.n, (px[1] - drag.y) * drag.mpp);
  } else {
    const p = onPlane(pg.viewer(), px, drag.point, drag.n);
    if (!p) return true;
    delta = sub(p, drag.point);
  }
  drag.y = px[1];
  if (len(delta) === 0) return true;
  const moved = pg.messages.guard(() => translateShape(drag.shape, delta));
  if (!moved) return true;
  drag.point = add(drag.point, delta);
  drag.shape = moved;
  drag.moved = true;
  return pg.edits.setShape(drag.id, drag.shape);
}

/**
 * @typedef {object} InputHost
 * @property {HTMLCanvasElement} canvas
 * @property {EventTarget} keys where the widget's keys are read
 * @property {() => any} viewer
 * @property {(origin: number[], direction: number[]) => any} pick the obstacle a ray hits
 * @property {(id: string) => object|undefined} shapeOf
 * @property {import('./scene-edits.js').SceneEdits} edits
 * @property {import('./pinning.js').Pinning} pinning
 * @property {import('./messages.js').Messages} messages
 * @property {(on?: boolean) => void} engage the wheel zooms (`on`), or back to the default
 * @property {() => boolean} engaged
 * @property {() => void} cameraMoved
 * @property {() => void} refreshSelected
 * @property {boolean} full a full widget (obstacle and pin keys)
 * @property {{ toggleRun: () => void, singleStep: () => void, reset: () => void, fit: () => void,
 *              toggleHelp: (show?: boolean) => void, showView: (view: string) => void }} commands
 */

/** @param {InputHost} pg */
export function wireInput(pg) {
  const canvas = pg.canvas;
  const pointers = new Map();
  let drag = null;
  let pinch = null;
  const dpr = () => window.devicePixelRatio || 1;
  const pinchState = () => {
    const [a, b] = [...pointers.values()];
    return { d: Math.hypot(a.x - b.x, a.y - b.y), x: (a.x + b.x) / 2, y: (a.y + b.y) / 2 };
  };
  canvas.addEventListener('contextmenu', (e) => e.preventDefault());
  canvas.addEventListener('pointerdown', (e) => {
    canvas.focus({ preventScroll: true });
    pg.engage(true);
    pointers.set(e.pointerId, { x: e.clientX, y: e.clientY });
    if (pointers.size === 2) {
      // A second finger: the gesture becomes a pinch (zoom) with a two-finger pan.
      drag = null;
      pinch = pinchState();
      return;
    }
    if (pointers.size > 2) return;
    canvas.setPointerCapture?.(e.pointerId);
    const px = pixel(canvas, e);
    const camera = e.button === 2 || e.button === 1 || e.shiftKey;
    // Pin mode: a click on a link pins a control point there (nothing is dragged).
    if (pg.pinning.mode && !camera && e.button === 0 && pg.pinning.pinAt(px)) return;
    if (!camera && e.button === 0) {
      const ray = pg.viewer().rayAt(px[0], px[1]);
      const hit = pg.messages.guard(() => pg.pick(ray.origin, ray.direction));
      if (hit) {
        pg.edits.select(hit.id);
        drag = obstacleDrag(pg, px, hit, e);
        const hand = grabbedHand(hit);
        if (hand && !e.altKey) Object.assign(drag, { hand, start: drag.point });
        return;
      }
    }
    drag = { kind: 'camera', x: e.clientX, y: e.clientY, pan: camera, moved: false };
  });
  const dragTo = (e) => {
    if (pointers.has(e.pointerId)) pointers.set(e.pointerId, { x: e.clientX, y: e.clientY });
    if (pinch && pointers.size === 2) {
      const now = pinchState();
      if (now.d > 1 && pinch.d > 1) pg.viewer().zoom(pinch.d / now.d);
      pg.viewer().pan((now.x - pinch.x) * dpr(), (now.y - pinch.y) * dpr());
      pg.cameraMoved();
      pinch = now;
      return;
    }
    if (!drag) return;
    if (drag.kind === 'camera') {
      const dx = (e.clientX - drag.x) * dpr();
      const dy = (e.clientY - drag.y) * dpr();
      drag.x = e.clientX;
      drag.y = e.clientY;
      if (!dx && !dy) return;
      drag.moved = true;
      if (drag.pan || pg.viewer().view !== '3d') pg.viewer().pan(dx, dy);
      else pg.viewer().orbit(dx, dy);
      pg.cameraMoved();
      return;
    }
    if (!moveObstacle(pg, drag, e)) drag = null;
  };
  canvas.addEventListener('pointermove', dragTo);
  const end = (e) => {
    // The browser may coalesce the last moves into the release: apply it.
    if (e.type === 'pointerup' && !pinch) dragTo(e);
    pointers.delete(e.pointerId);
    if (pinch) {
      if (pointers.size < 2) pinch = null;
      drag = null;
      return;
    }
    if (drag?.kind === 'camera' && !drag.moved && !drag.pan && e.type === 'pointerup') pg.edits.select(null);
    if (drag?.kind === 'obstacle') pg.refreshSelected();
    drag = null;
  };
  canvas.addEventListener('pointerup', end);
  canvas.addEventListener('pointercancel', end);
  canvas.addEventListener('dblclick', (e) => {
    e.preventDefault();
    pg.commands.fit();
  });
  canvas.addEventListener('blur', () => pg.engage());
  canvas.addEventListener('wheel', (e) => {
    if (!(pg.engaged() || e.ctrlKey || e.metaKey)) {
      // Let the page scroll; say how to zoom.
      pg.messages.hint('Click the view (or hold Ctrl) to zoom with the wheel');
      return;
    }
    e.preventDefault();
    // A pinch on a touchpad arrives as a Ctrl + wheel with small deltas.
    pg.viewer().zoom(Math.exp(e.deltaY * (e.ctrlKey ? 0.01 : 0.001)));
    pg.cameraMoved();
  }, { passive: false });
  pg.keys.addEventListener('keydown', (e) => onKey(pg, e));
}

const VIEWS = ['3d', 'top', 'front', 'side'];

function nextView(pg) {
  pg.commands.showView(VIEWS[(VIEWS.indexOf(pg.viewer().view) + 1) % VIEWS.length]);
}

/** The widget's keys (see the help box); keys typed into a field or on a button are theirs. */
export function onKey(pg, e) {
  const t = e.composedPath?.()[0] ?? e.target;
  if (t && ['INPUT', 'SELECT', 'TEXTAREA'].includes(t.tagName)) return;
  // Space and Enter press a focused button (or pick a focused list entry).
  if (t && (t.tagName === 'BUTTON' || t.tagName === 'LI' || t.tagName === 'SUMMARY') && (e.key === ' ' || e.key === 'Enter')) return;
  if (e.ctrlKey || e.metaKey || e.altKey) return;
  const actions = {
    ' ': () => pg.commands.toggleRun(),
    s: () => pg.commands.singleStep(),
    '.': () => pg.commands.singleStep(),
    r: () => pg.commands.reset(),
    f: () => pg.commands.fit(),
    Delete: () => pg.edits.removeSelected(),
    Backspace: () => pg.edits.removeSelected(),
    Escape: () => { pg.commands.toggleHelp(false); pg.edits.select(null); if (pg.pinning.mode) pg.pinning.setMode(false); },
    p: () => { if (pg.full) pg.pinning.setMode(); },
    '?': () => pg.commands.toggleHelp(),
    h: () => pg.commands.toggleHelp(),
    '[': () => pg.edits.editSelected((s) => scaleShape(s, 0.8)),
    ']': () => pg.edits.editSelected((s) => scaleShape(s, 1.25)),
    q: () => pg.edits.editSelected((s) => rotateShape(s, [0, 0, 1], Math.PI / 12)),
    e: () => pg.edits.editSelected((s) => rotateShape(s, [0, 0, 1], -Math.PI / 12)),
    v: () => nextView(pg),
  };
  const key = e.key.length === 1 ? e.key.toLowerCase() : e.key;
  let action = actions[key];
  const k = '1234567890'.indexOf(e.key);
  if (!action && k >= 0 && pg.full) action = () => pg.edits.addObstacle(PALETTE[k]);
  if (!action) return;
  e.preventDefault();
  action();
}
