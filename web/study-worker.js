// A Monte Carlo study off the page's thread (a module worker). The page
// posts { scenario, runs, seed, block }; the worker runs the study in blocks
// of `block` runs with the library's `monteCarloRuns`, posts
// { type: 'progress', done, runs } after each block, then
// { type: 'done', report } (merged by `monteCarloMerge`, rows kept) or
// { type: 'error', message }. The page cancels a study by terminating the
// worker: it never touches the page's world.
import { loadWasm } from './wasm.js';

let ready = null;

self.onmessage = async ({ data }) => {
  try {
    ready ??= loadWasm();
    const { monteCarloMerge, monteCarloRuns } = await ready;
    const { scenario, runs, seed, block } = data;
    const rows = [];
    for (let from = 0; from < runs; from += block) {
      rows.push(...monteCarloRuns(scenario, { seed, from, count: Math.min(block, runs - from) }));
      self.postMessage({ type: 'progress', done: rows.length, runs });
    }
    self.postMessage({ type: 'done', report: monteCarloMerge(rows, { rows: true }) });
  } catch (err) {
    self.postMessage({ type: 'error', message: err instanceof Error ? err.message : String(err) });
  }
};
