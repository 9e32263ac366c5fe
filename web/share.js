// The scene's ways in and out of the page as a scenario: *Open…* a file,
// *Share* a link that restores it exactly, a `#scenario=` link opened.
//
// Owns: whether the scene came from a shared link that it still matches
// (`fromShareLink`) and the fragment last seen (`lastHash`). Interface:
// `sim` (the scene to write), `messages`, `load(scenario, label)` (loads a
// scene; returns null or the refusal), `statusBox()` (where the link is
// shown), `share` (whether the page keeps links in its address bar).
import { errorText, h } from './dom.js';
import { decodeShare, encodeShare, readScenarioFile } from './scenario-io.js';

export class SceneLinks {
  /**
   * @param {{ sim: import('./sim.js').Sim, messages: import('./messages.js').Messages,
   *           load: (scenario: object, label: string) => string|null, statusBox: () => HTMLElement|null, share: boolean }} host
   */
  constructor(host) {
    this.host = host;
    this.fromShareLink = false;
    this.lastHash = undefined;
  }

  /** Loads a scenario file (*Open…*); a bad file leaves the scene as it was. */
  async loadFile(file) {
    if (!file) return;
    try {
      this.host.load(await readScenarioFile(file), `file "${file.name}"`);
    } catch (err) {
      this.host.messages.error(`${errorText(err)}\nThe current scene is unchanged.`);
    }
  }

  /** A URL that restores the current scene exactly. */
  shareUrl() {
    const url = new URL(location.href);
    url.hash = encodeShare(this.host.sim.currentScenario());
    return url.href;
  }

  /**
   * Copies a link to the scene as it is now and shows it in the panel. The
   * address bar is left alone, so a reload never brings back a stale scene.
   */
  share() {
    const url = this.shareUrl();
    const show = (said) => {
      const box = this.host.statusBox();
      if (!box) return;
      const field = h('input', { type: 'text', readonly: true, value: url, id: 'share-link', 'aria-label': 'link to this scene', onfocus: (e) => e.target.select() });
      box.replaceChildren(said, field);
    };
    show('Link to this scene:');
    navigator.clipboard?.writeText(url).then(() => show('Link copied:'), () => {});
    return url;
  }

  /** Drops a `#scenario=` the scene no longer matches from the address bar. */
  forget() {
    if (!this.fromShareLink || !location.hash.startsWith('#scenario=')) return;
    this.fromShareLink = false;
    history.replaceState(null, '', location.pathname + location.search);
    this.lastHash = '';
  }

  /** Loads the scenario carried by a URL fragment; returns false when there is none. */
  loadHash(hash) {
    let scenario;
    try {
      scenario = decodeShare(hash);
    } catch (err) {
      this.host.messages.error(`${errorText(err)}\nThe current scene is unchanged.`);
      return true;
    }
    if (!scenario) return false;
    this.fromShareLink = !this.host.load(scenario, 'shared scenario') && Boolean(this.host.share);
    return true;
  }
}
