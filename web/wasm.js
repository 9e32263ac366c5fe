// The wasm module as the widget loads it: the one place that names where it
// is. In the repository it is crate/pkg, served as ./pkg/ beside the page;
// the npm package (scripts/package.mjs) ships this folder with a wasm.js that
// imports the package's own web build instead. A static import, so that
// bundlers see the module and the wasm it locates with `new URL(…,
// import.meta.url)`; the wasm itself is fetched only by `loadWasm()`, and a
// failure there is shown in the widget.
import init, * as wasm from './pkg/skeleton_avoidance.js';

let ready = null;

/** Loads and initialises the wasm once per page; resolves to the module's exports. */
export function loadWasm() {
  ready ??= init().then(() => wasm);
  return ready;
}
