// The playground's end of the sensor bridge (scripts/bridge.mjs): a
// WebSocket to a bridge on this machine, opened only when the person opts
// in, only to this machine (127.0.0.1 or `localhost`: the bridge listens on
// 127.0.0.1). Each message is
// one keypoint frame in the world frame (web/keypoints.js `checkFrame`);
// anything else is dropped with a notice. Frames go to the `HumanFeed`,
// which keeps only the latest until the next drawn frame.
//
// Owns: the socket, the counts of frames and dropped messages.
// Interface: `offer(frame)` (to the feed), `notice(text, problem)` (the panel's
// camera line), `closed(reason)`.
import { checkFrame } from './keypoints.js';

const LOCAL = new Set(['127.0.0.1', 'localhost']);

/** `text` as a bridge address on this machine, or an Error naming why not. */
export function bridgeUrl(text) {
  let url;
  try {
    url = new URL(String(text).trim());
  } catch {
    throw new Error('bridge address: not a URL (ws://127.0.0.1:8765/)');
  }
  if (url.protocol !== 'ws:') throw new Error('bridge address: expected ws:// (a bridge on this machine)');
  if (!LOCAL.has(url.hostname)) throw new Error(`bridge address: only a bridge on this machine (localhost), not ${url.hostname}`);
  return url.href;
}

export class BridgeClient {
  constructor(host) {
    this.host = host;
    this.socket = null;
    this.frames = 0;
    this.dropped = 0;
    this.lastDrop = '';
  }

  /** Connects to `text` (checked by `bridgeUrl`; throws before connecting otherwise). */
  connect(text) {
    const url = bridgeUrl(text);
    this.close();
    const socket = new WebSocket(url);
    this.socket = socket;
    socket.onopen = () => this.host.notice(`Bridge connected (${url}); waiting for frames.`);
    socket.onerror = () => this.host.notice(`No bridge answered at ${url} (start it with: node scripts/bridge.mjs).`, true);
    socket.onclose = () => {
      if (this.socket === socket) {
        this.socket = null;
        this.host.closed(`Bridge closed after ${this.frames} frames.`);
      }
    };
    socket.onmessage = (e) => this.message(e.data);
  }

  /** One message: a frame to the feed, or dropped with a notice. */
  message(data) {
    let frame;
    try {
      if (typeof data !== 'string' || data.length > 4_000_000) throw new Error('message: not a text frame (or over 4 MB)');
      frame = checkFrame(JSON.parse(data));
    } catch (err) {
      this.dropped += 1;
      this.lastDrop = err instanceof SyntaxError ? 'not JSON' : err.message;
      this.host.notice(`Bridge: a message that is not a frame was dropped (${this.lastDrop}); ${this.dropped} so far.`, true);
      return;
    }
    this.frames += 1;
    this.host.offer({ ...frame, capturedAt: performance.now(), source: 'bridge' });
  }

  close() {
    const socket = this.socket;
    this.socket = null;
    socket?.close();
  }

  get open() {
    return this.socket !== null;
  }
}
