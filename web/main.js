// The playground page: one full <skeleton-playground> filling the window.
// `?scenario=<example>` picks the example; `?backend=`, `?view=`, `?speed=`
// and `?paused` are passed on to the element; `#scenario=…` (a shared link)
// restores a scene. `window.playground` is the hook the browser tests and the
// console use.
const params = new URLSearchParams(location.search);
const element = document.getElementById('playground');
for (const key of ['backend', 'view', 'speed', 'paused']) {
  if (params.has(key)) element.setAttribute(key, params.get(key));
}
element.setAttribute('scenario', params.get('scenario') ?? 'planar-transition');
const status = document.getElementById('page-status');

const playground = {
  /** Resolves once the first frames are drawn; rejects with the failure shown on the page. */
  // The element reads its attributes when it is defined: they are set above,
  // and the module defining it is loaded only now.
  ready: import('./embed.js').then(() => element.ready).then(() => {
    playground.backend = element.playground.backend;
    status.textContent = `Drawing with ${playground.backend === 'webgpu' ? 'WebGPU' : 'WebGL2'}. Press ? for the keys.`;
  }),
  /** `"webgpu"` or `"webgl2"` once ready. */
  backend: null,
  /** The Playground (panel, world, viewer). */
  get app() { return element.playground; },
  get viewer() { return element.playground?.viewer; },
  get world() { return element.playground?.world; },
  /** A snapshot: the viewer's state (backend, screenNodes…), the world's, frames, stats. */
  state() { return element.playground ? element.playground.snapshot() : { backend: null, frames: 0 }; },
  /** The plotted series: `{ clearance, dh, qdot }`, each `{ name: { t, v } }`. */
  series() {
    const p = element.playground.plots;
    return { clearance: p.clearance.data(), dh: p.dh.data(), qdot: p.qdot.data() };
  },
};
window.playground = playground;
playground.ready.catch((err) => {
  status.textContent = 'Stopped: see the message over the view.';
  console.warn(err);
});
