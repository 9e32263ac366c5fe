// The wasm module as the widget loads it: the one place that names where it
// is. In the repository (`npm start`) it is crate/pkg, served as ./pkg/
// beside the page, imported when first needed (so that Node can load the
// widget's modules for tests without it); the npm package
// (scripts/package.mjs), and with it the built site (scripts/site.mjs), ships
// this folder with a wasm.js that imports the package's own web build
// statically, so that bundlers see the module and the wasm it locates with
// `new URL(…, import.meta.url)`. A failure is shown in the widget.

let ready = null;

/** Loads and initialises the wasm once per page; resolves to the module's exports. */
export function loadWasm() {
  ready ??= import('./pkg/skeleton_avoidance.js').then(async (wasm) => {
    await wasm.default();
    return wasm;
  });
  return ready;
}
