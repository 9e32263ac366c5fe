// Helpers shared by the project's scripts: running commands, timing, paths.
import { spawnSync } from 'node:child_process';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

export const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');

/** The cargo bin directory, put on PATH so freshly installed tools are found. */
const cargoBin = path.join(process.env.CARGO_HOME ?? path.join(process.env.HOME ?? '/root', '.cargo'), 'bin');
if (!(process.env.PATH ?? '').split(path.delimiter).includes(cargoBin)) {
  process.env.PATH = `${cargoBin}${path.delimiter}${process.env.PATH ?? ''}`;
}

/** Runs a command with inherited output; returns its exit status (127 when missing). */
export function run(cmd, args, { cwd = repo, env = {} } = {}) {
  const r = spawnSync(cmd, args, { cwd, stdio: 'inherit', env: { ...process.env, ...env } });
  if (r.error) return r.error.code === 'ENOENT' ? 127 : 1;
  return r.status ?? 1;
}

/** Runs a command quietly; returns `{ status, stdout, stderr }` (status 127 when missing). */
export function capture(cmd, args, { cwd = repo } = {}) {
  const r = spawnSync(cmd, args, { cwd, encoding: 'utf8' });
  if (r.error) return { status: r.error.code === 'ENOENT' ? 127 : 1, stdout: '', stderr: String(r.error) };
  return { status: r.status ?? 1, stdout: r.stdout ?? '', stderr: r.stderr ?? '' };
}

export function seconds(t0) {
  return ((performance.now() - t0) / 1000).toFixed(1);
}
