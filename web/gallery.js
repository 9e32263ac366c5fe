// The primitive gallery page (gallery.html): every obstacle primitive the
// renderer draws, beside a planar arm with a control point, its distance line,
// repulsion arrow and an uncertainty region. A module of its own: the page's
// Content-Security-Policy forbids inline script.
import init, { Viewer, skeleton } from './pkg/skeleton_avoidance.js';
const params = new URLSearchParams(location.search);
const canvas = document.getElementById('view');
if (params.get('small') === '1') canvas.className = 'small';
async function start() {
  await init();
  const viewer = await Viewer.create(canvas, { backend: params.get('backend') ?? 'auto', view: params.get('view') ?? '3d', antialias: params.has('antialias') ? params.get('antialias') === 'true' : undefined });
  const robot = { preset: 'planar3' };
  viewer.setRobot(robot);
  const q = [0.4, 0.6, 0.5];
  const sk = skeleton(robot, q);
  const rot = [0, 0, Math.sin(0.3), Math.cos(0.3)];
  const obstacles = [
    { id: 'point', shape: { type: 'point', p: [0.6, -0.5, 0.1] } },
    { id: 'segment', shape: { type: 'segment', a: [0.4, -0.6, 0.0], b: [0.5, -0.3, 0.3] } },
    { id: 'sphere', shape: { type: 'sphere', center: [0.15, -0.5, 0.1], radius: 0.08 } },
    { id: 'capsule', shape: { type: 'capsule', a: [-0.2, -0.5, 0.05], b: [-0.05, -0.35, 0.2], radius: 0.05 } },
    { id: 'plane', shape: { type: 'plane', normal: [0, 0, 1], offset: 0.25 } },
    { id: 'rectangle', shape: { type: 'rectangle', center: [-0.4, 0.2, 0.1], axes: [[0, 1, 0], [0, 0, 1]], halfExtents: [0.12, 0.08] } },
    { id: 'disk', shape: { type: 'disk', center: [-0.35, -0.2, 0.1], normal: [1, 1, 0], radius: 0.1 } },
    { id: 'polygon', shape: { type: 'polygon', vertices: [[0.0, 0.5, 0.0], [0.25, 0.5, 0.0], [0.25, 0.65, 0.0], [0.12, 0.58, 0.0], [0.0, 0.7, 0.0]] } },
    { id: 'box', shape: { type: 'box', center: [0.75, 0.0, 0.08], halfExtents: [0.06, 0.1, 0.08], rotation: rot } },
    { id: 'human', shape: { type: 'human', position: [0.3, 0.9, 0] }, parts: [
      { type: 'sphere', center: [0.3, 0.9, 0.75], radius: 0.1 },
      { type: 'capsule', a: [0.3, 0.9, 0.2], b: [0.3, 0.9, 0.55], radius: 0.14 },
      { type: 'capsule', a: [0.12, 0.9, 0.55], b: [0.1, 0.75, 0.35], radius: 0.05 },
      { type: 'capsule', a: [0.48, 0.9, 0.55], b: [0.5, 0.75, 0.35], radius: 0.05 },
    ] },
  ];
  const tip = sk.nodes[sk.nodes.length - 1];
  const mid = sk.nodes[2].map((x, k) => 0.5 * (x + sk.nodes[3][k]));
  if (params.get('empty') !== '1') viewer.drawState({
    skeleton: sk,
    obstacles,
    controlPoints: [
      { position: tip, witness: [0.6, 0.0, 0.0], repulsion: [-0.4, 0.5, 0], transitioning: false },
      { position: mid, witness: [0.15, -0.42, 0.1], repulsion: [0.3, 0.3, 0], transitioning: true },
    ],
    uncertainty: [{ obstacle: 'sphere', radius: 0.04 }],
  });
  viewer.setSelected(params.get('selected') ?? 'box');
  if (params.get('grid') === '0') viewer.setDisplay({ grid: false, volumes: true, nodes: true, axes: false });
  viewer.zoom(1.4);
  const scale = Number(params.get('scale') ?? 1);
  const resize = () => viewer.resize(Math.round(canvas.clientWidth * scale), Math.round(canvas.clientHeight * scale));
  resize();
  let frames = 0;
  await new Promise((resolve) => {
    const frame = () => { viewer.render(); frames += 1; if (frames === 3) resolve(); requestAnimationFrame(frame); };
    requestAnimationFrame(frame);
  });
  window.gallery = { viewer, obstacles };
}
window.galleryReady = start().catch((err) => {
  document.getElementById('error').textContent = err instanceof Error ? err.message : String(err);
  throw err;
});
