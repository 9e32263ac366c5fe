// The docs page's Monte Carlo figure: 200 noisy copies of the `chattering`
// example run in a Web Worker, shown as a histogram and a table (the
// playground's Dependability panel, without the panel).
import { showReport, startStudy } from './dependability.js';
import { loadWasm } from './playground.js';

const $ = (id) => document.getElementById(id);
const d = { histogram: $('docs-study-histogram'), table: $('docs-study-table') };
let study = null;

$('docs-study-run').addEventListener('click', async () => {
  study?.cancel();
  const wasm = await loadWasm();
  const scenario = wasm.exampleScenario('chattering');
  const runs = 200;
  $('docs-study-progress').hidden = false;
  $('docs-study-message').textContent = 'starting…';
  const started = performance.now();
  study = startStudy({
    scenario,
    runs,
    seed: 1,
    onProgress: (done) => {
      $('docs-study-progress').value = done / runs;
      $('docs-study-message').textContent = `${done} / ${runs} runs`;
    },
    onDone: (report) => {
      $('docs-study-progress').hidden = true;
      $('docs-study-message').textContent = `${runs} runs in ${((performance.now() - started) / 1000).toFixed(1)} s`;
      showReport(d, report);
    },
    onError: (message) => {
      $('docs-study-progress').hidden = true;
      $('docs-study-message').textContent = `The study failed: ${message}`;
    },
  });
});
