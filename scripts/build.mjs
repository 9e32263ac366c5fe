// Builds the wasm packages with the pinned tools, never downloading:
//   crate/pkg       --target web, with the renderer (the playground)
//   crate/pkg-node  --target nodejs, the numerics only (Node tests, benches)
//
//   node scripts/build.mjs [web] [node] [--dev]
import path from 'node:path';
import { repo, run } from './lib.mjs';

export function buildWasm(which, { dev = false } = {}) {
  const profile = dev ? '--dev' : '--release';
  const targets = {
    web: ['build', profile, '--target', 'web', '--out-dir', 'pkg', '--mode', 'no-install', '--', '--features', 'render'],
    node: ['build', profile, '--target', 'nodejs', '--out-dir', 'pkg-node', '--mode', 'no-install'],
  };
  return run('wasm-pack', targets[which], { cwd: path.join(repo, 'crate') });
}

if (process.argv[1] && path.resolve(process.argv[1]) === path.join(repo, 'scripts', 'build.mjs')) {
  const dev = process.argv.includes('--dev');
  const which = process.argv.slice(2).filter((a) => !a.startsWith('--'));
  for (const w of which.length ? which : ['web', 'node']) {
    if (buildWasm(w, { dev }) !== 0) process.exit(1);
  }
}
