// The playground page: a planar 3-link arm drawn by the wgpu renderer, one
// slider per joint. `window.playground` is the hook the browser tests use.
import init, { Viewer } from '/pkg/skeleton_avoidance.js';

const params = new URLSearchParams(location.search);
const canvas = document.getElementById('view');
const status = document.getElementById('status');
const errorBox = document.getElementById('error');
const jointsBox = document.getElementById('joints');

let viewer = null;
let q = new Float64Array(0);
let viewChoice = params.get('view') ?? 'auto';

/** Shows a failure to the person (as text, never as HTML) and logs it. */
function showError(message) {
  errorBox.textContent = message;
  errorBox.hidden = false;
  status.textContent = 'Stopped: see the message over the view.';
}

function errorText(err) {
  return err instanceof Error ? err.message : String(err);
}

function resize() {
  if (!viewer) return;
  const dpr = window.devicePixelRatio || 1;
  const w = Math.max(1, Math.round(canvas.clientWidth * dpr));
  const h = Math.max(1, Math.round(canvas.clientHeight * dpr));
  viewer.resize(w, h);
}

function buildSliders(dof) {
  jointsBox.replaceChildren();
  for (let i = 0; i < dof; i++) {
    const row = document.createElement('div');
    row.className = 'joint';
    const label = document.createElement('label');
    label.textContent = `q${i + 1}`;
    label.htmlFor = `joint-${i}`;
    const slider = document.createElement('input');
    Object.assign(slider, { type: 'range', id: `joint-${i}`, min: -Math.PI, max: Math.PI, step: 0.01, value: 0 });
    slider.setAttribute('aria-label', `joint ${i + 1} (rad)`);
    const out = document.createElement('output');
    out.htmlFor = slider.id;
    const show = () => { out.textContent = `${(q[i] * 180 / Math.PI).toFixed(0)}°`; };
    slider.addEventListener('input', () => {
      q[i] = Number(slider.value);
      show();
      try {
        viewer.setJoints(q);
      } catch (err) {
        showError(errorText(err));
      }
    });
    show();
    row.append(label, slider, out);
    jointsBox.append(row);
  }
}

function wireCamera() {
  let drag = null;
  canvas.addEventListener('contextmenu', (e) => e.preventDefault());
  canvas.addEventListener('pointerdown', (e) => {
    drag = { x: e.clientX, y: e.clientY, pan: e.button === 2 || e.button === 1 || e.shiftKey };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener('pointermove', (e) => {
    if (!drag || !viewer) return;
    const dpr = window.devicePixelRatio || 1;
    const dx = (e.clientX - drag.x) * dpr;
    const dy = (e.clientY - drag.y) * dpr;
    drag.x = e.clientX;
    drag.y = e.clientY;
    // The 2D views cannot orbit: a plain drag pans them.
    if (drag.pan || viewer.view !== '3d') viewer.pan(dx, dy);
    else viewer.orbit(dx, dy);
  });
  const end = () => { drag = null; };
  canvas.addEventListener('pointerup', end);
  canvas.addEventListener('pointercancel', end);
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    if (viewer) viewer.zoom(Math.exp(e.deltaY * 0.001));
  }, { passive: false });

  const select = document.getElementById('view-select');
  select.value = viewChoice;
  select.addEventListener('change', () => {
    viewChoice = select.value;
    try {
      viewer.setView(viewChoice);
    } catch (err) {
      showError(errorText(err));
    }
  });
  const display = () => viewer.setDisplay({
    volumes: document.getElementById('show-volumes').checked,
    nodes: document.getElementById('show-nodes').checked,
    axes: document.getElementById('show-axes').checked,
    grid: true,
  });
  for (const id of ['show-volumes', 'show-nodes', 'show-axes']) {
    document.getElementById(id).addEventListener('change', display);
  }
}

let frames = 0;
let firstFrame;
const firstFrameDrawn = new Promise((resolve) => { firstFrame = resolve; });

function frame() {
  try {
    viewer.render();
  } catch (err) {
    showError(errorText(err));
    return;
  }
  frames += 1;
  if (frames === 2) firstFrame();
  requestAnimationFrame(frame);
}

async function start() {
  await init();
  const backend = params.get('backend') ?? 'auto';
  viewer = await Viewer.create(canvas, { backend, view: viewChoice });
  viewer.setRobot({ preset: 'planar3' });
  q = new Float64Array(viewer.dof);
  buildSliders(viewer.dof);
  wireCamera();
  resize();
  new ResizeObserver(resize).observe(canvas);
  playground.backend = viewer.backend;
  status.textContent = `Drawing with ${viewer.backend === 'webgpu' ? 'WebGPU' : 'WebGL2'} · planar 3-link arm (0.4 / 0.3 / 0.2 m)`;
  requestAnimationFrame(frame);
  await firstFrameDrawn;
}

const ready = start();
const playground = {
  /** Resolves once the first frames are drawn; rejects with the failure shown on the page. */
  ready,
  /** `"webgpu"` or `"webgl2"` once ready. */
  backend: null,
  /** The wasm `Viewer` once ready (for tests and the console). */
  get viewer() {
    return viewer;
  },
  /** A snapshot: backend, q, nodes, screenNodes, view, surface format… */
  state() {
    return viewer ? { ...viewer.state(), frames } : { backend: null, frames };
  },
};
window.playground = playground;
ready.catch((err) => {
  showError(`The playground could not start.\n${errorText(err)}`);
});
