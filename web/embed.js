// <skeleton-playground>: the playground as a custom element, for any plain
// HTML page with one module script:
//
//   <script type="module" src="embed.js"></script>
//   <skeleton-playground scenario="planar-transition" controls="minimal"></skeleton-playground>
//
// Attributes (read when the element is connected):
//   scenario  an example name (see exampleScenarioNames()), a URL of a JSON
//             scenario file (ending in .json), or inline scenario JSON
//   controls  "full" (panel and plots), "minimal" (run / reset bar, default), "none"
//   plot      with controls="minimal": one plot under the view ("clearance", "dh", "qdot")
//   backend   "auto" (default), "webgpu", "webgl2"
//   view      "auto" (default), "3d", "top", "front", "side"
//   speed     simulation speed factor (default 1)
//   paused    start paused
//   stats     show the stats overlay (always shown with controls="full")
//   share     read the scenario from the page URL's #scenario= fragment when present
//             and follow later changes of it (for a page hosting one full playground)
//   autoplay  run from page load; by default a widget runs only while it is on
//             screen (it starts when scrolled into view and waits off screen)
//   fill      the widget is the page: the wheel always zooms, touch never scrolls
//
// The element's `playground` property is the Playground once `ready` resolves.
import { Playground, loadWasm } from './playground.js';
import { parseScenarioText } from './scenario-io.js';

export { Playground, loadWasm };

async function resolveScenario(attr) {
  const text = (attr ?? '').trim();
  if (text === '') return 'planar-transition';
  if (text.startsWith('{')) return parseScenarioText(text, 'The scenario attribute');
  if (/\.json($|\?)/.test(text)) {
    const url = new URL(text, document.baseURI);
    const response = await fetch(url);
    if (!response.ok) throw new Error(`The scenario file ${url.pathname} could not be fetched (HTTP ${response.status}).`);
    return parseScenarioText(await response.text(), `The scenario file ${url.pathname}`);
  }
  return text;
}

export class SkeletonPlayground extends HTMLElement {
  constructor() {
    super();
    this.attachShadow({ mode: 'open' });
    let resolve;
    let reject;
    /** Resolves to the Playground once the first frames are drawn; rejects with the failure shown inside. */
    this.ready = new Promise((res, rej) => { resolve = res; reject = rej; });
    this.ready.catch(() => {});
    this.settle = { resolve, reject };
    this.playground = null;
  }

  connectedCallback() {
    if (this.started) return;
    this.started = true;
    const controls = this.getAttribute('controls') ?? 'minimal';
    const pg = new Playground(this.shadowRoot, {
      controls,
      backend: this.getAttribute('backend') ?? undefined,
      view: this.getAttribute('view') ?? undefined,
      speed: this.hasAttribute('speed') ? Number(this.getAttribute('speed')) : 1,
      plot: this.getAttribute('plot') ?? undefined,
      stats: this.hasAttribute('stats'),
      keyboardTarget: this.hasAttribute('fill') ? window : undefined,
      captureWheel: this.hasAttribute('fill'),
      share: this.hasAttribute('share'),
      presetMeshes: this.getAttribute('preset-meshes') ?? undefined,
      estimator: this.getAttribute('estimator') ?? undefined,
    });
    this.playground = pg;
    if (this.hasAttribute('paused')) pg.toggleRun();
    if (!this.hasAttribute('autoplay') && typeof IntersectionObserver === 'function') {
      // Off screen the simulation waits, so a reader finds each widget at its start.
      pg.setOffscreen(true);
      this.observer = new IntersectionObserver((entries) => {
        for (const entry of entries) pg.setOffscreen(!entry.isIntersecting);
      }, { threshold: 0.25 });
      this.observer.observe(this);
    }
    (async () => {
      const scenario = await resolveScenario(this.getAttribute('scenario'));
      await pg.start(scenario);
      if (this.hasAttribute('share')) {
        pg.loadHash(location.hash);
        window.addEventListener('hashchange', () => {
          if (location.hash !== pg.lastHash) pg.loadHash(location.hash);
        });
      }
      return pg;
    })().then(this.settle.resolve, (err) => {
      const message = err instanceof Error ? err.message : String(err);
      pg.showError(`The playground could not start.\n${message}`);
      this.settle.reject(err);
    });
  }

  disconnectedCallback() {
    // Elements moved within the page reconnect; only a removed element is freed.
    queueMicrotask(() => {
      if (this.isConnected) return;
      this.observer?.disconnect();
      this.playground?.destroy();
    });
  }
}

if (!customElements.get('skeleton-playground')) customElements.define('skeleton-playground', SkeletonPlayground);
