// Static server for the playground: web/ at "/", the wasm package crate/pkg at
// "/pkg/", the presets' meshes (crate/tests/data) at "/robots/", the camera's
// pose estimator (scripts/estimator-files.mjs, from node_modules) at
// "/estimator/". No dependencies; used by `npm start` and by the browser tests.
// With `--root dist` it serves the built site as it is (the npm package's
// files in skeleton-avoidance/, scripts/site.mjs); any
// other folder (an absolute path) is served as it is too.
//
//   node scripts/serve.mjs [--port 8080] [--host 127.0.0.1] [--root web|dist]
import http from 'node:http';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { estimatorFile } from './estimator-files.mjs';

const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');

const TYPES = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8',
  '.css': 'text/css; charset=utf-8',
  '.json': 'application/json; charset=utf-8',
  '.wasm': 'application/wasm',
  '.png': 'image/png',
  '.svg': 'image/svg+xml',
  '.md': 'text/plain; charset=utf-8',
  '.txt': 'text/plain; charset=utf-8',
};

/** Sends `file` (404 naming `pathname` when it cannot be read, or `file` is null). */
function send(res, file, pathname) {
  if (file === null) {
    res.writeHead(404, { 'content-type': 'text/plain' });
    res.end(`not found: ${pathname}\n`);
    return;
  }
  fs.readFile(file, (err, data) => {
    if (err) {
      send(res, null, pathname);
      return;
    }
    res.writeHead(200, {
      'content-type': TYPES[path.extname(file)] ?? 'application/octet-stream',
      'cache-control': 'no-store',
    });
    res.end(data);
  });
}

/**
 * Starts the server; resolves to `{ server, url }` once it listens. With
 * `root: 'web'`, `tree` is the checkout whose web/, wasm package and meshes
 * are served (another build's, for `npm run bench -- --frames --against`),
 * and `pkg` a wasm package served instead of the tree's.
 */
export function serve({ port = 8080, host = '127.0.0.1', root = 'web', tree = repo, pkg = path.join(tree, 'crate', 'pkg') } = {}) {
  const mounts = root === 'web'
    ? [['/pkg/', path.resolve(pkg)], ['/robots/', path.join(tree, 'crate', 'tests', 'data')], ['/', path.join(tree, 'web')]]
    : [['/', path.resolve(repo, root)]];
  const server = http.createServer((req, res) => {
    const url = new URL(req.url ?? '/', 'http://localhost');
    let pathname = decodeURIComponent(url.pathname);
    if (pathname.endsWith('/')) pathname += 'index.html';
    // The estimator's files by name only (a fixed list: nothing else of node_modules).
    const estimator = root === 'web' && pathname.startsWith('/estimator/') ? estimatorFile(pathname.slice('/estimator/'.length)) : undefined;
    if (estimator !== undefined) {
      send(res, estimator, pathname);
      return;
    }
    for (const [prefix, dir] of mounts) {
      if (!pathname.startsWith(prefix)) continue;
      const file = path.join(dir, pathname.slice(prefix.length));
      if (!file.startsWith(dir)) break; // no escaping the mount
      send(res, file, pathname);
      return;
    }
    res.writeHead(404, { 'content-type': 'text/plain' });
    res.end(`not found: ${pathname}\n`);
  });
  return new Promise((resolve, reject) => {
    server.once('error', reject);
    server.listen(port, host, () => {
      const { port: actual } = server.address();
      resolve({ server, url: `http://${host}:${actual}/` });
    });
  });
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const arg = (name, fallback) => {
    const i = process.argv.indexOf(`--${name}`);
    return i > 0 ? process.argv[i + 1] : fallback;
  };
  const { url } = await serve({
    port: Number(arg('port', process.env.PORT ?? 8080)),
    host: arg('host', '127.0.0.1'),
    root: arg('root', 'web'),
  });
  console.log(`Playground: ${url}  (Ctrl-C to stop)`);
}
