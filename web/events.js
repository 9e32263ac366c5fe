// The world's events as a person reads them: one sentence per kind, bursts
// of the same kind merged into one line ("segment switch ×312"), the events
// that stop or endanger the robot pinned until dismissed, and a scrollable,
// filterable log whose entries move the plots' cursor to their time.
//
// While the robot is stopped only what changes its state is shown (a stopped
// arm's control points keep switching as the obstacle moves: that is noise).
import { h } from './dom.js';

/** Kinds that stay on screen until dismissed. */
const PINNED = new Set(['stop', 'chattering', 'unavoidable']);
/**
 * Kinds the log alone reports while it is on screen: the control points'
 * routine travel along the skeleton, which the view shows as it happens.
 * Notices over the view are kept for what asks for attention; with a person
 * walking by the arm these came several a second and covered the robot.
 */
const ROUTINE = new Set(['segmentSwitch', 'transitionStart', 'transitionEnd']);
/** Kinds shown while the robot is stopped. */
const STATE_CHANGES = new Set(['stop', 'resume', 'chattering', 'unavoidable', 'lock', 'unlock']);
/** Two events of one kind closer than this (s of simulation time) are one burst. */
const BURST_GAP = 0.5;
/** How long a merged notice stays after its last event (ms of wall time). */
const NOTICE_MS = 3500;
/** Most notices kept at once (pinned ones first); the first alone is shown
 * until the person asks for the others: the view is for the arm. */
const MAX_NOTICES = 4;
/** Most rows kept in the log. */
const MAX_LOG = 400;

const LABEL = {
  segmentSwitch: 'segment switch',
  transitionStart: 'transition starts',
  transitionEnd: 'transition ends',
  switchRisk: 'sensing error may switch the segment',
  transitionTooSlow: 'transition slower than the time to collision',
  chattering: 'chattering',
  stop: 'robot stopped',
  resume: 'robot resumes',
  lock: 'control point locked',
  unlock: 'control point unlocked',
  unavoidable: 'collision cannot be avoided',
  staleSensing: 'sensed person is stale',
};

/** The short name of a kind ("segment switch"); unknown kinds are spelled out from camelCase. */
export function kindLabel(kind) {
  return LABEL[kind] ?? String(kind).replace(/([a-z])([A-Z])/g, '$1 $2').toLowerCase();
}

const seg = (i) => (Number.isInteger(i) ? `segment ${i + 1}` : 'a segment');
const num = (x, digits = 2) => (Number.isFinite(x) ? x.toFixed(digits) : '?');
const on = (e) => (e.obstacle ? ` (${e.obstacle})` : '');

/** One readable sentence for an event of any kind. */
export function describe(e) {
  switch (e.kind) {
    case 'segmentSwitch': return `control point${on(e)} switches from ${seg(e.from)} to ${seg(e.to)}`;
    case 'transitionStart': return `control point${on(e)} travels from ${seg(e.from)} to ${seg(e.to)} in ${num(e.duration)} s${e.replan ? ' (replanned)' : ''}`;
    case 'transitionEnd': return `control point${on(e)} arrives on ${seg(e.segment)}`;
    case 'switchRisk': return `sensing error${on(e)} may switch ${seg(e.segment)} to ${seg(e.alternative)} (gap ${num(e.gap * 1000, 0)} mm < margin ${num(e.margin * 1000, 0)} mm)`;
    case 'transitionTooSlow': return `transition needs ${num(e.remaining)} s but collision${on(e)} in ${num(e.timeToCollision)} s`;
    case 'chattering': return `chattering${on(e)}: ${e.switches ?? '?'} segment switches in the window`;
    case 'stop': return `robot stopped${e.reason ? `: ${e.reason}` : ''}`;
    case 'resume': return 'robot resumes';
    case 'lock': return `control point${on(e)} locked on ${seg(e.segment)} until ${num(e.until)} s`;
    case 'unlock': return `control point${on(e)} unlocked`;
    case 'staleSensing': return `no good frame of ${e.obstacle}:${e.part} for ${num(e.age)} s: margin grown to ${num(e.margin * 1000, 0)} mm`;
    case 'unavoidable': return `collision cannot be avoided${on(e)}${e.reason ? `: ${e.reason}` : ''}`;
    default: return kindLabel(e.kind);
  }
}

const tText = (a, b) => (b - a > 5e-4 ? `t ${a.toFixed(3)}–${b.toFixed(3)} s` : `t ${a.toFixed(3)} s`);

export class EventFeed {
  /**
   * @param {{ notices: HTMLElement, log?: HTMLElement, onSeek?: (t: number) => void, onNotices?: () => void }} parts
   *   `notices` over the view; `log`, when given, receives the log's list and filter;
   *   `onNotices` is called when notices come or go (to place them).
   */
  constructor({ notices, log, onSeek, onNotices }) {
    this.notices = notices;
    this.onSeek = onSeek;
    this.onNotices = onNotices;
    // One line over the view: the first notice, and how many more there are.
    this.more = h('button', { type: 'button', class: 'more', hidden: true, 'aria-expanded': 'false',
      onclick: () => this.expand(!this.notices.classList.contains('expanded')) });
    notices.append(this.more);
    this.stopped = false;
    this.live = new Map();
    this.rows = [];
    this.filter = { kind: '', text: '' };
    this.suppressed = 0;
    this.pending = [];
    if (log) this.buildLog(log);
  }

  buildLog(container) {
    this.kindSelect = h('select', { id: 'log-kind', 'aria-label': 'show events of kind', onchange: () => this.applyFilter() },
      h('option', { value: '' }, 'all kinds'), h('option', { value: 'important' }, 'stops and risks'));
    this.textFilter = h('input', { type: 'search', id: 'log-filter', placeholder: 'filter', 'aria-label': 'filter events by text', oninput: () => this.applyFilter() });
    this.list = h('ol', { class: 'log-list', id: 'event-log', 'aria-label': 'event log', tabindex: '0' });
    this.empty = h('p', { class: 'hint log-empty' }, 'No events yet.');
    container.append(h('div', { class: 'log-head' }, h('strong', {}, 'events'), this.kindSelect, this.textFilter), this.empty, this.list);
  }

  /** Forgets everything (a new or restarted world). */
  clear() {
    this.pending = [];
    this.stopped = false;
    this.suppressed = 0;
    for (const n of this.live.values()) clearTimeout(n.timer);
    this.live.clear();
    this.notices.replaceChildren(this.more);
    this.expand(false);
    this.rows = [];
    this.list?.replaceChildren();
    if (this.empty) this.empty.hidden = false;
  }

  /**
   * Takes the new events of one frame, oldest first, and keeps them for the
   * next `flush`, or shows them at once when one is pinned (a stop). The
   * playground flushes as it refreshes its plots: on software rendering a
   * frame in which the page's text changes costs a composite of the page,
   * and a person walking by the arm makes events nearly every frame.
   */
  queue(events) {
    for (const e of events) this.pending.push(e);
    if (events.some((e) => PINNED.has(e.kind))) this.flush();
  }

  /** Shows the queued events. */
  flush() {
    if (this.pending.length === 0) return;
    const events = this.pending;
    this.pending = [];
    this.push(events);
  }

  /** Shows the new events of one frame, oldest first, at once. */
  push(events) {
    // Without a log on screen (an embed with minimal controls) every kind is a notice.
    const logShown = Boolean(this.list?.getClientRects().length);
    for (const e of events) {
      const t = Number(e.t);
      if (this.stopped && !STATE_CHANGES.has(e.kind)) {
        this.suppressed += 1;
        continue;
      }
      if (e.kind === 'stop') this.stopped = true;
      if (e.kind === 'resume') this.stopped = false;
      if (!(ROUTINE.has(e.kind) && logShown)) this.notice(e, t);
      this.log(e, t);
    }
  }

  notice(e, t) {
    const key = e.kind;
    let n = this.live.get(key);
    if (n && t - n.t1 <= BURST_GAP) {
      n.count += 1;
      n.t1 = t;
      n.last = e;
    } else {
      if (n) this.retire(key);
      const pinned = PINNED.has(e.kind);
      const text = h('span');
      const el = h('div', { class: `notice ${e.kind}${pinned ? ' pinned' : ''}`, role: pinned ? 'alert' : undefined }, text);
      if (pinned) el.append(h('button', { type: 'button', class: 'dismiss', 'aria-label': 'dismiss', title: 'dismiss', onclick: () => this.retire(key) }, '×'));
      n = { el, text, t0: t, t1: t, count: 1, last: e, pinned };
      this.live.set(key, n);
      if (pinned) this.notices.prepend(el);
      else this.notices.insertBefore(el, this.more);
      this.trimNotices();
      this.changed();
    }
    const many = n.count > 1 ? `${kindLabel(e.kind)} ×${n.count}` : describe(e);
    n.text.textContent = `${tText(n.t0, n.t1)} · ${many}`;
    // Two lines at most are shown; the whole sentence on hover (and in the log).
    n.el.title = n.text.textContent;
    if (!n.pinned) {
      clearTimeout(n.timer);
      n.timer = setTimeout(() => this.retire(key), NOTICE_MS);
    }
  }

  retire(key) {
    const n = this.live.get(key);
    if (!n) return;
    clearTimeout(n.timer);
    n.el.remove();
    this.live.delete(key);
    this.changed();
  }

  /** Shows all notices (`true`) or the first alone. */
  expand(all) {
    this.notices.classList.toggle('expanded', all);
    this.more.setAttribute('aria-expanded', String(all));
    this.changed();
  }

  changed() {
    const others = this.live.size - 1;
    const all = this.notices.classList.contains('expanded');
    this.more.hidden = others < 1;
    this.more.textContent = all ? 'fewer' : `+${others}`;
    this.more.title = all ? 'show the first notice only' : `show ${others} more notice${others > 1 ? 's' : ''}`;
    this.onNotices?.();
  }

  trimNotices() {
    const unpinned = [...this.live.entries()].filter(([, n]) => !n.pinned);
    let extra = this.live.size - MAX_NOTICES;
    for (const [key] of unpinned) {
      if (extra-- <= 0) break;
      this.retire(key);
    }
  }

  log(e, t) {
    if (!this.list) return;
    const last = this.rows[this.rows.length - 1];
    if (last && last.kind === e.kind && t - last.t1 <= BURST_GAP) {
      last.count += 1;
      last.t1 = t;
      this.fillRow(last, e);
      return;
    }
    const row = { kind: e.kind, t0: t, t1: t, count: 1, first: e };
    row.el = h('li', { class: `log-row ${e.kind}`, tabindex: '-1', onclick: () => this.onSeek?.(row.t0),
      onkeydown: (ev) => { if (ev.key === 'Enter') this.onSeek?.(row.t0); } });
    this.fillRow(row, e);
    this.rows.push(row);
    this.list.append(row.el);
    if (this.empty) this.empty.hidden = true;
    if (![...this.kindSelect.options].some((o) => o.value === e.kind)) this.kindSelect.append(h('option', { value: e.kind }, kindLabel(e.kind)));
    while (this.rows.length > MAX_LOG) this.rows.shift().el.remove();
    this.showRow(row);
    // Follow the newest entry unless the person scrolled up to read.
    const l = this.list;
    if (l.scrollHeight - l.scrollTop - l.clientHeight < 40) l.scrollTop = l.scrollHeight;
  }

  fillRow(row, e) {
    row.el.textContent = `${tText(row.t0, row.t1)} · ${row.count > 1 ? `${kindLabel(e.kind)} ×${row.count} (first: ${describe(row.first)})` : describe(e)}`;
  }

  showRow(row) {
    const { kind, text } = this.filter;
    const kindOk = kind === '' || (kind === 'important' ? PINNED.has(row.kind) || row.kind === 'transitionTooSlow' || row.kind === 'switchRisk' : row.kind === kind);
    row.el.hidden = !(kindOk && (text === '' || row.el.textContent.toLowerCase().includes(text)));
  }

  applyFilter() {
    this.filter = { kind: this.kindSelect.value, text: this.textFilter.value.trim().toLowerCase() };
    for (const row of this.rows) this.showRow(row);
  }

  /** What the feed shows now, for tests: `{ notices: [text], log: [text], suppressed }`. */
  snapshot() {
    return {
      notices: [...this.notices.querySelectorAll('.notice')].map((n) => n.firstChild.textContent),
      pinned: [...this.live.values()].filter((n) => n.pinned).map((n) => n.text.textContent),
      log: this.rows.map((r) => r.el.textContent),
      suppressed: this.suppressed,
    };
  }
}
