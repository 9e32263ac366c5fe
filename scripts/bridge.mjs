// The sensor bridge: keypoint frames from any sensor program (a depth
// camera's body tracker, MediaPipe, a motion-capture stream) to the
// playground. It reads frames as JSON lines from its standard input and
// from sensor programs connected by WebSocket at ws://127.0.0.1:PORT/sensor,
// and forwards them to the playgrounds connected at ws://127.0.0.1:PORT/
// (the playground's *sensor bridge* box, opted in by the person).
//
//   python3 my_tracker.py | node scripts/bridge.mjs [--port 8765] [--rate 60]
//
// One frame per line (docs/bridge.md has the format and a few lines of
// Python that write it):
//   {"t": 12.345, "layout": "coco17", "keypoints": [[x, y, z], ...], "confidence": [...]}
// metres in the robot's (world) frame, z up. A line that is not a frame is
// dropped with a notice on stderr. Frames are never queued: the latest one
// is kept and sent at most `rate` times a second (the playground gives the
// latest to the world once per drawn frame), and a playground that has not
// taken the previous one (its socket's buffer) skips a turn.
//
// Only this machine: it listens on 127.0.0.1 and refuses a playground whose
// page is not served from localhost.
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { WebSocketServer } from 'ws';
import { checkFrame } from '../web/keypoints.js';

/** A line longer than this is dropped (bytes). */
export const MAX_LINE = 4_000_000;
/** A playground whose socket holds more than this unsent skips frames. */
const MAX_BUFFERED = 1_000_000;

const LOCAL_ORIGIN = /^https?:\/\/(127\.0\.0\.1|localhost|\[::1\])(:\d+)?$/;

/**
 * Starts a bridge on 127.0.0.1:`port` (0: any free port). `notice(text)`
 * gets each dropped line's reason. Resolves to `{ url, stats, line(text),
 * close() }`; `line` takes one JSON line (what stdin and sensors give).
 */
export function startBridge({ port = 8765, rate = 60, notice = (t) => console.error(t) } = {}) {
  if (!(rate > 0 && rate <= 1000)) throw new Error('rate: expected frames per second in (0, 1000]');
  if (!(Number.isInteger(port) && port >= 0 && port < 65536)) throw new Error('port: expected a port number');
  const stats = { received: 0, dropped: 0, forwarded: 0, thinned: 0, skipped: 0 };
  const players = new Set();
  let latest = null;
  const wss = new WebSocketServer({
    host: '127.0.0.1',
    port,
    maxPayload: MAX_LINE,
    verifyClient: ({ origin, req }) => {
      const url = new URL(req.url ?? '/', 'http://127.0.0.1');
      // Sensor programs send no Origin; a browser page must be this machine's.
      if (url.pathname === '/sensor') return origin === undefined || LOCAL_ORIGIN.test(origin);
      return url.pathname === '/' && (origin === undefined || LOCAL_ORIGIN.test(origin));
    },
  });
  const line = (text) => {
    const s = String(text).trim();
    if (!s) return;
    try {
      if (s.length > MAX_LINE) throw new Error(`line: longer than ${MAX_LINE} bytes`);
      const frame = JSON.stringify(checkFrame(JSON.parse(s)));
      // A frame not sent yet is replaced: thinned, never queued.
      if (latest !== null) stats.thinned += 1;
      latest = frame;
      stats.received += 1;
    } catch (err) {
      stats.dropped += 1;
      const why = err instanceof SyntaxError ? 'not JSON' : err.message;
      if (stats.dropped <= 5 || stats.dropped % 100 === 0) notice(`bridge: dropped a line that is not a frame (${why}); ${stats.dropped} so far`);
    }
  };
  wss.on('connection', (socket, req) => {
    if (new URL(req.url ?? '/', 'http://127.0.0.1').pathname === '/sensor') {
      socket.on('message', (data, binary) => {
        for (const l of (binary ? '' : data.toString('utf8')).split('\n')) line(l);
        if (binary) line('binary message');
      });
    } else {
      players.add(socket);
      socket.on('close', () => players.delete(socket));
    }
  });
  const timer = setInterval(() => {
    if (latest === null) return;
    const frame = latest;
    latest = null;
    for (const p of players) {
      if (p.readyState !== 1 || p.bufferedAmount > MAX_BUFFERED) {
        stats.skipped += 1;
        continue;
      }
      p.send(frame);
      stats.forwarded += 1;
    }
  }, 1000 / rate);
  return new Promise((resolve, reject) => {
    wss.once('error', reject);
    wss.once('listening', () => {
      const { port: actual } = wss.address();
      resolve({
        url: `ws://127.0.0.1:${actual}/`,
        stats,
        line,
        get players() { return players.size; },
        close: () => new Promise((done) => {
          clearInterval(timer);
          for (const p of players) p.terminate();
          wss.close(() => done());
        }),
      });
    });
  });
}

/** Splits a stream into lines, dropping (with a notice) any longer than MAX_LINE. */
export function readLines(stream, onLine, notice) {
  let buffer = '';
  let skipping = false;
  stream.setEncoding('utf8');
  stream.on('data', (chunk) => {
    let start = 0;
    for (let i = chunk.indexOf('\n'); i >= 0; i = chunk.indexOf('\n', start)) {
      const piece = chunk.slice(start, i);
      if (!skipping) onLine(buffer + piece);
      buffer = '';
      skipping = false;
      start = i + 1;
    }
    if (!skipping) buffer += chunk.slice(start);
    if (buffer.length > MAX_LINE) {
      notice(`bridge: dropped a line longer than ${MAX_LINE} bytes`);
      buffer = '';
      skipping = true;
    }
  });
  stream.on('end', () => { if (!skipping && buffer) onLine(buffer); });
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const arg = (name, fallback) => {
    const i = process.argv.indexOf(`--${name}`);
    return i > 0 ? process.argv[i + 1] : fallback;
  };
  const bridge = await startBridge({ port: Number(arg('port', 8765)), rate: Number(arg('rate', 60)) });
  console.error(`bridge: playgrounds connect to ${bridge.url} (the panel's "sensor bridge"); sensors write JSON lines to stdin or to ${bridge.url}sensor`);
  if (!process.stdin.isTTY) readLines(process.stdin, bridge.line, (t) => console.error(t));
  setInterval(() => {
    const s = bridge.stats;
    console.error(`bridge: ${s.received} frames in, ${s.forwarded} sent to ${bridge.players} playground(s), ${s.thinned} thinned, ${s.dropped} dropped`);
  }, 10_000).unref();
}
