// Builds the wasm packages with the pinned tools, never downloading:
//   crate/pkg       --target web, with the renderer (the playground)
//   crate/pkg-node  --target nodejs, the numerics only (Node tests, benches),
//                   built for speed (LLVM inline threshold 1000, wasm-opt -O3)
//                   in its own target directory, target/node
//
//   node scripts/build.mjs [web] [node] [--dev]
import crypto from 'node:crypto';
import fs from 'node:fs';
import path from 'node:path';
import zlib from 'node:zlib';
import { repo, run } from './lib.mjs';

/** Features the module uses, for binaryen. */
const WASM_FEATURES = ['simd', 'bulk-memory', 'nontrapping-float-to-int', 'sign-ext', 'mutable-globals', 'reference-types', 'multivalue'];

/**
 * Optimises a release module with binaryen's `wasm-opt` at `level` (the
 * pinned npm package; Debian's binaryen corrupts this module): `-Oz` shrinks
 * the web build, `-O3` speeds up the Node build's control step. The result
 * is cached by the input's hash and the level under target/, so an
 * unchanged module costs nothing. Returns the gzipped size in bytes.
 */
export function shrinkWasm(file, level = '-Oz') {
  const wasmOpt = path.join(repo, 'node_modules', '.bin', 'wasm-opt');
  const input = fs.readFileSync(file);
  if (fs.existsSync(wasmOpt)) {
    const hash = crypto.createHash('sha256').update(input).digest('hex').slice(0, 16);
    const cacheDir = path.join(repo, 'target', 'wasm-opt-cache');
    const cached = path.join(cacheDir, `${hash}${level === '-Oz' ? '' : level}.wasm`);
    if (!fs.existsSync(cached)) {
      fs.mkdirSync(cacheDir, { recursive: true });
      console.log(`build: wasm-opt ${level} (about a minute, once per change of the module)`);
      const status = run(wasmOpt, [level, ...WASM_FEATURES.map((f) => `--enable-${f}`), file, '-o', `${cached}.tmp`]);
      if (status !== 0) return -1;
      fs.renameSync(`${cached}.tmp`, cached);
    }
    fs.copyFileSync(cached, file);
  }
  return zlib.gzipSync(fs.readFileSync(file), { level: 6 }).length;
}

/**
 * The release Node build's compiler settings. V8 does not inline calls
 * between wasm functions, so LLVM inlines more (threshold 1000 against its
 * default 250 at -O3): the Node module grows from 2.52 to 4.07 MB (0.99 to 1.42 MB
 * gzipped) and the control step gets faster (docs/speed.md). The Node build
 * has no size budget of its own (the npm package's, scripts/package.mjs,
 * counts it); the web build keeps the default. `RUSTFLAGS` replaces
 * the config's flags, so it repeats `+simd128` from .cargo/config.toml; the
 * changed flags would rebuild every crate each time the two builds alternate,
 * hence a target directory of its own.
 */
const NODE_BUILD_ENV = {
  RUSTFLAGS: '-C target-feature=+simd128 -C llvm-args=-inline-threshold=1000',
  CARGO_TARGET_DIR: path.join(repo, 'target', 'node'),
};

export function buildWasm(which, { dev = false } = {}) {
  const profile = dev ? '--dev' : '--release';
  const targets = {
    web: ['build', profile, '--target', 'web', '--out-dir', 'pkg', '--mode', 'no-install', '--', '--features', 'render'],
    node: ['build', profile, '--target', 'nodejs', '--out-dir', 'pkg-node', '--mode', 'no-install'],
  };
  const env = which === 'node' && !dev ? NODE_BUILD_ENV : {};
  const status = run('wasm-pack', targets[which], { cwd: path.join(repo, 'crate'), env });
  if (status !== 0 || dev) return status;
  if (which === 'node') {
    // The Node build (tests, benches, studies) is optimised for speed with
    // `wasm-opt -O3`: in one `npm run bench` table (load ~16 on 2 cores) the
    // control step with 100 / 1000 spheres went from 410 / 3249 to 274 / 2849 µs.
    return shrinkWasm(path.join(repo, 'crate', 'pkg-node', 'skeleton_avoidance_bg.wasm'), '-O3') < 0 ? 1 : 0;
  }
  const gz = shrinkWasm(path.join(repo, 'crate', 'pkg', 'skeleton_avoidance_bg.wasm'));
  if (gz < 0) return 1;
  console.log(`build: crate/pkg wasm ${(gz / 1e6).toFixed(3)} MB gzipped (budget 1.86 MB: scripts/site.mjs, tests/package/pages.mjs)`);
  return 0;
}

if (process.argv[1] && path.resolve(process.argv[1]) === path.join(repo, 'scripts', 'build.mjs')) {
  const dev = process.argv.includes('--dev');
  const which = process.argv.slice(2).filter((a) => !a.startsWith('--'));
  for (const w of which.length ? which : ['web', 'node']) {
    if (buildWasm(w, { dev }) !== 0) process.exit(1);
  }
}
