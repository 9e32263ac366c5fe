// A URDF and its meshes into the page: a dropped folder, a zip, or picked
// files; the robot's volumes are fitted to its collision meshes (`fitUrdf`)
// and the meshes drawn (`Viewer.setUrdf`).
//
// Owns: the last fit's report (`report`: coverage before and after).
// Interface: `sim` (the library, the current scenario's timing), `messages`,
// `load(scenario, label)` (loads a scene; null or the refusal) and
// `showUrdf(xml, meshes)` (the viewer draws the URDF's meshes, framed).
//
// Caps (a hostile drop keeps the page responsive and loads nothing from the
// offending file): 2000 files, 32 MiB per file, 256 MiB in all, zip entries
// unpacked only up to those sizes (a zip bomb stops at the cap), paths that
// climb out of the folder (`..`, absolute) skipped and named.
import { errorText } from './dom.js';

export const MAX_FILES = 2000;
export const MAX_FILE_BYTES = 32 << 20;
export const MAX_TOTAL_BYTES = 256 << 20;

const safePath = (p) => {
  const parts = p.replaceAll('\\', '/').split('/').filter((c) => c !== '' && c !== '.');
  return p.startsWith('/') || parts.includes('..') ? null : parts.join('/');
};

/** Every file under the dropped items, with its path (folders walked). */
async function dropped(dataTransfer) {
  const out = [];
  const walk = async (entry, prefix) => {
    if (out.length > MAX_FILES) return;
    if (entry.isFile) {
      out.push({ path: prefix + entry.name, file: await new Promise((ok, ko) => entry.file(ok, ko)) });
    } else if (entry.isDirectory) {
      const reader = entry.createReader();
      for (;;) {
        const batch = await new Promise((ok, ko) => reader.readEntries(ok, ko));
        if (batch.length === 0) break;
        for (const e of batch) await walk(e, `${prefix}${entry.name}/`);
      }
    }
  };
  const entries = [...dataTransfer.items].map((i) => i.webkitGetAsEntry?.()).filter(Boolean);
  if (entries.length === 0) return [...dataTransfer.files].map((file) => ({ path: file.name, file }));
  for (const e of entries) await walk(e, '');
  return out;
}

/** Bytes of a readable stream, refused past `cap` (the zip-bomb guard). */
async function capped(stream, cap, name) {
  const chunks = [];
  let total = 0;
  for (const reader = stream.getReader(); ;) {
    const { done, value } = await reader.read();
    if (done) break;
    total += value.length;
    if (total > cap) {
      await reader.cancel();
      throw new Error(`${name}: unpacks to more than ${cap} bytes`);
    }
    chunks.push(value);
  }
  const out = new Uint8Array(total);
  let at = 0;
  for (const c of chunks) { out.set(c, at); at += c.length; }
  return out;
}

/**
 * The files of a zip archive (stored or deflated entries), within the caps:
 * `budget` bytes in all (what the other files left of MAX_TOTAL_BYTES).
 */
export async function unzip(bytes, name, problems, budget = MAX_TOTAL_BYTES) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  let eocd = -1;
  for (let i = bytes.length - 22; i >= Math.max(0, bytes.length - 65557); i--) {
    if (view.getUint32(i, true) === 0x06054b50) { eocd = i; break; }
  }
  if (eocd < 0) throw new Error(`${name}: not a zip archive`);
  const count = view.getUint16(eocd + 10, true);
  if (count > MAX_FILES) throw new Error(`${name}: ${count} entries is more than ${MAX_FILES}`);
  let at = view.getUint32(eocd + 16, true);
  const out = [];
  let total = 0;
  for (let k = 0; k < count; k++) {
    if (at + 46 > bytes.length || view.getUint32(at, true) !== 0x02014b50) throw new Error(`${name}: damaged central directory`);
    const method = view.getUint16(at + 10, true);
    const packed = view.getUint32(at + 20, true);
    const nameLength = view.getUint16(at + 28, true);
    const skip = nameLength + view.getUint16(at + 30, true) + view.getUint16(at + 32, true);
    const local = view.getUint32(at + 42, true);
    const path = new TextDecoder().decode(bytes.subarray(at + 46, at + 46 + nameLength));
    at += 46 + skip;
    if (path.endsWith('/')) continue;
    const safe = safePath(path);
    if (!safe) { problems.push(`${name}: "${path}" leads outside the folder; skipped`); continue; }
    if (local + 30 > bytes.length) throw new Error(`${name}: damaged entry "${path}"`);
    const start = local + 30 + view.getUint16(local + 26, true) + view.getUint16(local + 28, true);
    const data = bytes.subarray(start, start + packed);
    if (data.length < packed) throw new Error(`${name}: entry "${path}" is truncated`);
    const room = Math.min(MAX_FILE_BYTES, budget - total);
    try {
      let file;
      if (method === 0) {
        if (data.length > room) throw new Error(`${name}: "${path}" is larger than ${room} bytes`);
        file = data.slice();
      } else if (method === 8) {
        file = await capped(new Blob([data]).stream().pipeThrough(new DecompressionStream('deflate-raw')), room, `${name}: "${path}"`);
      } else {
        problems.push(`${name}: "${path}" uses compression method ${method}; skipped`);
        continue;
      }
      total += file.length;
      out.push({ path: safe, bytes: file });
    } catch (err) {
      problems.push(errorText(err));
    }
  }
  return out;
}

/** `[{ path, bytes }]` from `{ path, file }` items (zips unpacked), within the caps. */
async function readAll(items, problems) {
  const out = [];
  let total = 0;
  for (const { path, file } of items.slice(0, MAX_FILES)) {
    const safe = safePath(path);
    if (!safe) { problems.push(`"${path}" leads outside the folder; skipped`); continue; }
    if (file.size > MAX_FILE_BYTES || total + file.size > MAX_TOTAL_BYTES) {
      problems.push(`"${path}": ${file.size} bytes is past the cap (${MAX_FILE_BYTES} per file, ${MAX_TOTAL_BYTES} in all); skipped`);
      continue;
    }
    const bytes = new Uint8Array(await file.arrayBuffer());
    if (/\.zip$/i.test(path)) {
      // The unpacked entries count against the total, not the packed zip.
      const entries = await unzip(bytes, path, problems, MAX_TOTAL_BYTES - total);
      for (const e of entries) total += e.bytes.length;
      out.push(...entries);
    } else {
      total += bytes.length;
      out.push({ path: safe, bytes });
    }
  }
  if (items.length > MAX_FILES) problems.push(`only the first ${MAX_FILES} files were read`);
  return out;
}

const percent = (x) => `${(100 * x).toFixed(1)} %`;

export class UrdfLoading {
  /**
   * @param {{ sim: import('./sim.js').Sim, messages: import('./messages.js').Messages,
   *           load: (scenario: object, label: string) => string|null, showUrdf: (xml: string, meshes: object) => void }} host
   */
  constructor(host) {
    this.host = host;
    this.report = null;
  }

  /** Loads a URDF and its meshes from dropped items or picked files. */
  async loadItems(items) {
    const problems = [];
    let files;
    try {
      files = await readAll(items, problems);
    } catch (err) {
      this.host.messages.error(`${errorText(err)}\nThe current scene is unchanged.`);
      return;
    }
    const urdfs = files.filter((f) => /\.urdf$/i.test(f.path)).sort((a, b) => a.path.length - b.path.length);
    if (urdfs.length === 0) {
      this.host.messages.error(`No .urdf file among the ${files.length} files given.${problems.length ? `\n${problems.join('\n')}` : ''}\nThe current scene is unchanged.`);
      return;
    }
    const xml = new TextDecoder().decode(urdfs[0].bytes);
    const meshes = Object.fromEntries(files.filter((f) => !/\.urdf$/i.test(f.path)).map((f) => [f.path, f.bytes]));
    this.load(xml, meshes, urdfs[0].path, problems);
  }

  /** Fits, loads and draws a URDF with its mesh files; reports the figures and every problem. */
  load(xml, meshes, name, problems = []) {
    const { sim, messages } = this.host;
    let fit;
    try {
      fit = sim.wasm.fitUrdf(xml, { meshes });
    } catch (err) {
      messages.error(`The URDF "${name}" could not be loaded; the current scene is unchanged.\n${errorText(err)}`);
      return null;
    }
    const scenario = { robot: fit.robot, obstacles: [], dt: sim.scenario?.dt ?? 0.001, duration: sim.scenario?.duration ?? 10 };
    if (this.host.load(scenario, `URDF ${name}`)) return null;
    this.host.showUrdf(xml, meshes);
    const all = [...problems, ...fit.problems];
    const figures = fit.after
      ? `Volumes fitted to ${fit.after.bodies.length} collision meshes: vertices inside ${percent(fit.before.robot.vertexCoverage)} → ${percent(fit.after.robot.vertexCoverage)}, surface within ${fit.after.surfaceTolerance * 1000} mm ${percent(fit.before.robot.surfaceCoverage)} → ${percent(fit.after.robot.surfaceCoverage)}, excess ${fit.before.robot.excess.toFixed(2)} → ${fit.after.robot.excess.toFixed(2)}.`
      : 'No collision mesh could be read: radii as imported.';
    this.report = fit;
    messages.status(`Loaded URDF ${name}. ${figures}`);
    if (all.length) messages.error(`Loaded "${name}" with what was found; not loaded:\n${all.join('\n')}`);
    return fit;
  }

  /** Handles a drop on the view: a folder, a zip or files holding a URDF. */
  async drop(event) {
    event.preventDefault();
    const items = await dropped(event.dataTransfer);
    await this.loadItems(items);
  }
}
