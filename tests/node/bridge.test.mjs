// The sensor bridge (scripts/bridge.mjs) in Node: frames written as JSON
// lines reach a connected playground; a line that is not a frame is dropped
// with a notice; a flood is thinned (the latest frame is kept, never a
// queue); a page from another origin and a non-loopback path are refused.
// Every wait is for an event (a message, a close), never for a time.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { PassThrough } from 'node:stream';
import { once } from 'node:events';
import WebSocket from 'ws';
import { readLines, startBridge } from '../../scripts/bridge.mjs';

const frame = (t, x = 0) => ({ t, layout: 'coco17', keypoints: Array.from({ length: 17 }, (_, k) => [x, 0.01 * k, 1]) });

async function player(url, headers = { origin: 'http://127.0.0.1:8080' }) {
  const ws = new WebSocket(url, { headers });
  await once(ws, 'open');
  return ws;
}

test('frames reach the playground; a line that is not a frame is dropped with a notice', async () => {
  const notices = [];
  const bridge = await startBridge({ port: 0, notice: (t) => notices.push(t) });
  try {
    const ws = await player(bridge.url);
    const got = once(ws, 'message');
    bridge.line('{"t": 1, "layout": "coco17"}');
    bridge.line('not json');
    bridge.line(JSON.stringify({ ...frame(1), keypoints: frame(1).keypoints.map((p, k) => (k === 3 ? [0, null, 0] : p)) }));
    bridge.line(JSON.stringify(frame(2, 0.5)));
    const [data] = await got;
    assert.deepEqual(JSON.parse(data.toString()), frame(2, 0.5));
    assert.equal(bridge.stats.dropped, 3);
    assert.match(notices[0], /dropped a line that is not a frame \(keypoints: expected an array\)/);
    assert.match(notices[1], /not JSON/);
    assert.match(notices[2], /keypoints\[3\]: expected three finite numbers/);
    ws.close();
  } finally {
    await bridge.close();
  }
});

test('a flood is thinned to the latest frame, never queued', async () => {
  const bridge = await startBridge({ port: 0, rate: 30, notice: () => {} });
  try {
    const ws = await player(bridge.url);
    const got = once(ws, 'message');
    // Ten thousand frames at once, far faster than the bridge sends.
    for (let i = 1; i <= 10_000; i++) bridge.line(JSON.stringify(frame(i)));
    const [data] = await got;
    // The frame sent is the latest one written; all the earlier ones were replaced, not kept.
    assert.equal(JSON.parse(data.toString()).t, 10_000);
    assert.equal(bridge.stats.received, 10_000);
    assert.equal(bridge.stats.thinned, 9_999);
    ws.close();
  } finally {
    await bridge.close();
  }
});

test('sensors may write JSON lines on a WebSocket too; stdin lines are split and an endless line is dropped', async () => {
  const bridge = await startBridge({ port: 0, notice: () => {} });
  try {
    const ws = await player(bridge.url);
    const sensor = new WebSocket(`${bridge.url}sensor`);
    await once(sensor, 'open');
    const got = once(ws, 'message');
    sensor.send(`${JSON.stringify(frame(5))}\n`);
    const [data] = await got;
    assert.equal(JSON.parse(data.toString()).t, 5);
    sensor.close();
    ws.close();
  } finally {
    await bridge.close();
  }
  const lines = [];
  const notices = [];
  const input = new PassThrough();
  readLines(input, (l) => lines.push(l), (t) => notices.push(t));
  input.write('{"a":');
  input.write('1}\n{"b":2}\n');
  input.write('x'.repeat(4_000_001));
  input.write('still the long line\n{"c":3}\n');
  input.end();
  await once(input, 'end');
  assert.deepEqual(lines, ['{"a":1}', '{"b":2}', '{"c":3}']);
  assert.equal(notices.length, 1);
});

test('only pages of this machine may connect; bad options are refused', async () => {
  const bridge = await startBridge({ port: 0, notice: () => {} });
  try {
    const ws = new WebSocket(bridge.url, { headers: { origin: 'https://example.org' } });
    const [err] = await once(ws, 'error');
    assert.match(err.message, /401|403|Unexpected server response/);
    const other = new WebSocket(`${bridge.url}elsewhere`, { headers: { origin: 'http://localhost:8080' } });
    await once(other, 'error');
    assert.equal(bridge.players, 0);
  } finally {
    await bridge.close();
  }
  assert.throws(() => startBridge({ port: 0, rate: 0 }), /^Error: rate:/);
  assert.throws(() => startBridge({ port: 70_000 }), /^Error: port:/);
});
