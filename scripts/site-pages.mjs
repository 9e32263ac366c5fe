// The built site's pages on the npm package: the site (scripts/site.mjs) holds
// the packed package's browser files, unpacked from target/npm/*.tgz into
// `skeleton-avoidance/`, and the pages of web/ beside them. Only a page and
// the scripts of its own (main.js, docs-study.js, gallery.js: modules that are
// not part of the element) are copied from web/; every reference of theirs to
// a module of the element becomes `./skeleton-avoidance/element/<module>` and
// to the wasm-bindgen module `./skeleton-avoidance/web/skeleton_avoidance.js`,
// so the docs page, the embedding example and the playground run on exactly
// the files an npm user gets and cannot drift from them.
// tests/package/site.test.mjs serves the docs page and the embedding example
// from a folder holding nothing but the package and those pages.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { repo, capture } from './lib.mjs';

/** The folder of the site that holds the package's files. */
export const PACKAGE_DIR = 'skeleton-avoidance';

/** Folders of the package a browser page never loads (Node's build; the inlined-wasm entries). */
const NOT_FOR_PAGES = ['node', 'compat'];

const web = path.join(repo, 'web');

/** The packed tarball (target/npm/*.tgz); throws when there is not exactly one. */
export function packedTarball() {
  const dir = path.join(repo, 'target', 'npm');
  const found = fs.existsSync(dir) ? fs.readdirSync(dir).filter((f) => f.endsWith('.tgz')) : [];
  if (found.length !== 1) throw new Error(`site: expected one packed package in target/npm, found ${found.length} (node scripts/package.mjs builds it)`);
  return path.join(dir, found[0]);
}

/**
 * Unpacks the tarball's `package/` into `root/skeleton-avoidance/`, leaving
 * out Node's build and the compat entries unless `all`.
 */
export function unpackPackage(tarball, root, { all = false } = {}) {
  const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'skeleton-avoidance-site-'));
  try {
    const tar = capture('tar', ['-xzf', tarball, '-C', tmp]);
    if (tar.status !== 0) throw new Error(`site: could not unpack ${tarball}: ${tar.stderr}`);
    const dest = path.join(root, PACKAGE_DIR);
    fs.rmSync(dest, { recursive: true, force: true });
    fs.cpSync(path.join(tmp, 'package'), dest, {
      recursive: true,
      filter: (src) => all || !NOT_FOR_PAGES.includes(path.relative(path.join(tmp, 'package'), src).split(path.sep)[0]),
    });
    return dest;
  } finally {
    fs.rmSync(tmp, { recursive: true, force: true });
  }
}

/** Relative module references of an HTML page or a script: `src="./x.js"`, `from './x.js'`, `import('./x.js')`, `new URL('./x.js', …)`. */
const REFERENCE = /(src="|from\s+'|import\(\s*'|new URL\(\s*')\.\/([\w./-]+\.js)(['"])/g;

/**
 * Writes each page of `pages` (names in web/) into `root`, with the scripts
 * of its own, every reference to the package rewritten. `root` must already
 * hold the package (unpackPackage). Returns the files copied from web/, and
 * throws when a reference leads to no file of the package or of the page.
 */
export function writePages(root, pages) {
  const pkgRoot = path.join(root, PACKAGE_DIR);
  const element = new Set(fs.readdirSync(path.join(pkgRoot, 'element')));
  const copied = new Set();
  const queue = [...pages];
  while (queue.length) {
    const file = queue.shift();
    if (copied.has(file)) continue;
    copied.add(file);
    const text = fs.readFileSync(path.join(web, file), 'utf8').replace(REFERENCE, (all, before, target, after) => {
      if (target === 'pkg/skeleton_avoidance.js') return `${before}./${PACKAGE_DIR}/web/skeleton_avoidance.js${after}`;
      if (element.has(target)) return `${before}./${PACKAGE_DIR}/element/${target}${after}`;
      if (target.includes('/') || !fs.existsSync(path.join(web, target))) {
        throw new Error(`site: ${file} refers to ./${target}, which is neither in the package nor a script of the page`);
      }
      queue.push(target);
      return all;
    });
    fs.writeFileSync(path.join(root, file), text);
  }
  for (const file of copied) {
    for (const [, , target] of fs.readFileSync(path.join(root, file), 'utf8').matchAll(REFERENCE)) {
      if (!fs.existsSync(path.join(root, target))) throw new Error(`site: ${file} refers to ./${target}, which the site lacks`);
    }
  }
  return [...copied].sort();
}
