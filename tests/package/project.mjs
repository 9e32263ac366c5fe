// A fresh temporary npm project with the packed package installed (offline,
// from target/npm/*.tgz, which the `package` layer of npm test builds).
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { spawnSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';

export const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..');
export const tsc = path.join(repo, 'node_modules', '.bin', 'tsc');

/** Runs a command; `{ status, out }` with stdout and stderr together. */
export function sh(cmd, args, cwd) {
  const r = spawnSync(cmd, args, { cwd, encoding: 'utf8', maxBuffer: 1 << 28 });
  return { status: r.status, out: `${r.stdout ?? ''}${r.stderr ?? ''}` };
}

/** Creates the project (`prefix` names the temp folder); returns its path. */
export function installPackage(prefix) {
  const npmDir = path.join(repo, 'target', 'npm');
  const tarballs = fs.existsSync(npmDir) ? fs.readdirSync(npmDir).filter((f) => f.endsWith('.tgz')) : [];
  assert.equal(tarballs.length, 1, 'run `node scripts/package.mjs` first (the package layer of npm test does)');
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), `skeleton-avoidance-${prefix}-`));
  fs.writeFileSync(path.join(dir, 'package.json'), JSON.stringify({ name: 'consumer', private: true, type: 'module' }));
  const install = sh('npm', ['install', '--no-audit', '--no-fund', '--offline', path.join(npmDir, tarballs[0])], dir);
  assert.equal(install.status, 0, install.out);
  return dir;
}
