// The widget's frame: the view with its overlays (stats, HUD, notices, the
// hint, the error box, the keyboard help), the plots' strip with the event
// log, and a minimal widget's run / reset bar; a full widget's drawer
// button. The parts fill it with their own elements.
//
// Owns: the container, the help box, the notices' box, the log, the bar's
// title and run button. Interface: the options and the kind of controls,
// the canvas, the overlays and the plots' strip to place, `messages` (its
// hint and error boxes), `onDrop` (files dropped on the view) and the bar's
// three commands.
import { h } from './dom.js';
import { followStats } from './notice-place.js';
import { STYLE } from './style.js';

/**
 * Whether the browser's WebGPU adapter is a software rasteriser (SwiftShader):
 * the renderer then draws without multisampling, which halves its cost there.
 * (Under WebGL2 the renderer reads the adapter name itself.)
 */
export async function softwareWebGpu() {
  try {
    const info = (await navigator.gpu?.requestAdapter())?.info;
    return Boolean(info && (info.isFallbackAdapter || /swiftshader|llvmpipe|lavapipe/i.test(`${info.architecture} ${info.description}`)));
  } catch {
    return false;
  }
}

// ---- the widget ----

const HELP = [
  ['Space', 'pause / run'],
  ['S or .', 'single control step (while paused)'],
  ['R', 'reset the simulation and the view'],
  ['F or double click', 'frame the robot and the obstacles'],
  ['1 … 0', 'add point, segment, sphere, capsule, plane, rectangle, disk, polygon, box, human'],
  ['Click', 'select an obstacle (drag it on the plane facing you)'],
  ['P, then click the arm', 'pin a control point on the link clicked (selection: pinned)'],
  ['Alt + drag', 'move the obstacle along the view direction'],
  ['Delete', 'delete the selected obstacle'],
  ['[ / ]', 'shrink / grow the selected obstacle'],
  ['Q / E', 'rotate the selected obstacle about z'],
  ['Escape', 'deselect, leave Pin mode, close this help'],
  ['V', 'next camera view'],
  ['Drag empty space', 'orbit (3D) or pan (2D); right or Shift + drag pans'],
  ['Wheel', 'zoom once the view was clicked (or with Ctrl held); two fingers pinch'],
  ['?', 'this help'],
];

export class WidgetFrame {
  /**
   * @param {{ options: object, controls: string, canvas: HTMLCanvasElement, overlays: HTMLElement[],
   *           messages: import('./messages.js').Messages, plots: HTMLElement, onDrop: (e: DragEvent) => void,
   *           bar: { toggleRun: () => void, reset: () => void, fit: () => void } }} host
   */
  constructor(host) {
    const { options, controls, messages } = host;
    this.style = h('style', {}, STYLE);
    this.notices = h('div', { class: 'notices', id: 'notices', 'aria-live': 'polite' });
    this.helpBox = h('div', { class: 'help', id: 'help', hidden: true },
      h('strong', {}, 'Keyboard and mouse'),
      h('table', {}, HELP.map(([k, what]) => h('tr', {}, h('td', {}, h('kbd', {}, k)), h('td', {}, what)))),
      h('p', { class: 'hint' }, 'Press ? or Escape to close.'));
    const [statsBox] = host.overlays;
    const stage = h('div', { class: 'stage' }, host.canvas, ...host.overlays, this.notices, messages.hintBox, messages.errorBox, this.helpBox);
    followStats(stage, statsBox);
    // A folder, a zip or files holding a URDF and its meshes, dropped on the view.
    stage.addEventListener('dragover', (e) => e.preventDefault());
    stage.addEventListener('drop', host.onDrop);
    if (controls === 'full') {
      stage.append(h('button', { type: 'button', class: 'panel-toggle', id: 'panel-toggle', 'aria-controls': 'panel', 'aria-expanded': 'false',
        onclick: (e) => e.currentTarget.setAttribute('aria-expanded', String(this.container.classList.toggle('panel-open'))) }, '☰ Controls'));
    }
    this.log = controls === 'full' ? h('section', { class: 'log', id: 'log', 'aria-label': 'event log' }) : null;
    if (this.log) host.plots.append(this.log);
    const cls = `sp ${controls}${options.plot ? ' with-plot' : ''}${options.stats ? ' with-stats' : ''}`;
    this.container = h('div', { class: cls }, stage, host.plots);
    if (controls === 'minimal') this.container.append(this.buildBar(host.bar));
  }

  buildBar(bar) {
    this.title = h('span', { class: 'title' });
    this.playButton = h('button', { type: 'button', onclick: bar.toggleRun }, 'Pause');
    return h('div', { class: 'bar' },
      this.playButton,
      h('button', { type: 'button', onclick: bar.reset, title: 'restart and frame the view' }, 'Reset'),
      h('button', { type: 'button', onclick: bar.fit, title: 'frame the robot and the obstacles (F, double click)' }, 'Fit'),
      this.title);
  }

  /** A drawer panel (narrow widgets) would cover the arm: closes it. */
  closeDrawer() {
    if (!this.container.classList.contains('panel-open')) return;
    this.container.classList.remove('panel-open');
    this.container.querySelector('#panel-toggle')?.setAttribute('aria-expanded', 'false');
  }

  /** Shows or hides the keyboard help (`show` omitted: toggles). */
  toggleHelp(show) {
    this.helpBox.hidden = show === undefined ? !this.helpBox.hidden : !show;
  }
}
