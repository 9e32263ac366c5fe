// What the widget tells the person outside the event feed: the error box
// over the view (a failure, with a *dismiss* button), the short hint over
// the view (how to zoom, Pin mode) and the status line of the panel.
//
// Owns: the error box, the hint box and its timer. Interface: `statusBox()`,
// the panel's status line or null (a widget without the panel). Every other
// part reports through `error`, `status`, `hint` and `guard`.
import { errorText, h } from './dom.js';

export class Messages {
  /** @param {{ statusBox: () => HTMLElement|null }} host */
  constructor(host) {
    this.host = host;
    this.errorMessage = h('span');
    this.errorBox = h('div', { class: 'error', id: 'error', role: 'alert', hidden: true },
      h('button', { type: 'button', onclick: () => { this.errorBox.hidden = true; } }, 'dismiss'), this.errorMessage);
    this.hintBox = h('div', { class: 'hint-box', id: 'view-hint', hidden: true, 'aria-live': 'polite' });
  }

  /** Shows `message` over the view until dismissed. */
  error(message) {
    this.errorMessage.textContent = message;
    this.errorBox.hidden = false;
  }

  clearError() {
    this.errorBox.hidden = true;
  }

  /** The panel's status line (nothing without a panel). */
  status(text) {
    const box = this.host.statusBox();
    if (box) box.textContent = text;
  }

  /** A short hint over the view, hidden after a while. */
  hint(text) {
    this.hintBox.textContent = text;
    this.hintBox.hidden = false;
    clearTimeout(this.hintTimer);
    this.hintTimer = setTimeout(() => { this.hintBox.hidden = true; }, 1800);
  }

  /**
   * Runs `f`; a throw is shown in `box` (a message line of the panel) or
   * over the view, and `undefined` returned. A success clears `box`.
   */
  guard(f, box) {
    try {
      const r = f();
      if (box) box.textContent = '';
      return r;
    } catch (err) {
      if (box) box.textContent = errorText(err);
      else this.error(errorText(err));
      return undefined;
    }
  }
}
