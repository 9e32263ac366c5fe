// Helpers of the URDF browser tests: the UR5 of crate/tests/data (licences
// there) as files, a folder on disk or a zip; screenshots of the view and
// their differences; the meshes / volumes toggles; a real drop of files or
// folders on the view (CDP `Input.dispatchDragEvent`, the path the browser
// takes for a drag from the desktop: folders arrive as directory entries).
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import zlib from 'node:zlib';
import { frames, artifacts, repo } from './chromium.mjs';
import { decodePng, pixel, colourDistance } from './png.mjs';

export const data = (p) => path.join(repo, 'crate', 'tests', 'data', p);
export const UR5_PARTS = ['base', 'shoulder', 'upperarm', 'forearm', 'wrist1', 'wrist2', 'wrist3'];
export const ur5Urdf = () => fs.readFileSync(data('urdf/ur5_robot.urdf'));
export const ur5Mesh = (part) => fs.readFileSync(data(`meshes/ur5/collision/${part}.stl`));

/**
 * The UR5 laid out as a ROS package under `root/name`: `urdf/ur5_robot.urdf`
 * and `meshes/ur5/collision/<part>.stl`; `replace` maps a part to other bytes
 * (or `null`: left out). Returns the folder.
 */
export function ur5Folder(root, name, replace = {}) {
  const dir = path.join(root, name);
  fs.mkdirSync(path.join(dir, 'urdf'), { recursive: true });
  fs.mkdirSync(path.join(dir, 'meshes', 'ur5', 'collision'), { recursive: true });
  fs.writeFileSync(path.join(dir, 'urdf', 'ur5_robot.urdf'), ur5Urdf());
  for (const part of UR5_PARTS) {
    const bytes = part in replace ? replace[part] : ur5Mesh(part);
    if (bytes) fs.writeFileSync(path.join(dir, 'meshes', 'ur5', 'collision', `${part}.stl`), bytes);
  }
  return dir;
}

export const tempRoot = () => fs.mkdtempSync(path.join(os.tmpdir(), 'skeleton-urdf-'));

/**
 * A zip archive of `entries` ({ name, bytes, deflate?, declared? }): stored,
 * or deflated when `deflate`; `declared` overrides the uncompressed size
 * written in the headers (a bomb lies about it).
 */
export function zip(entries) {
  const locals = [];
  const central = [];
  let offset = 0;
  for (const { name, bytes, deflate = false, declared } of entries) {
    const packed = deflate ? zlib.deflateRawSync(bytes, { level: 9 }) : bytes;
    const nameBytes = Buffer.from(name, 'utf8');
    const crc = zlib.crc32(bytes);
    const size = declared ?? bytes.length;
    const local = Buffer.alloc(30);
    local.writeUInt32LE(0x04034b50, 0);
    local.writeUInt16LE(20, 4);
    local.writeUInt16LE(deflate ? 8 : 0, 8);
    local.writeUInt32LE(crc, 14);
    local.writeUInt32LE(packed.length, 18);
    local.writeUInt32LE(size, 22);
    local.writeUInt16LE(nameBytes.length, 26);
    const dir = Buffer.alloc(46);
    dir.writeUInt32LE(0x02014b50, 0);
    dir.writeUInt16LE(20, 4);
    dir.writeUInt16LE(20, 6);
    dir.writeUInt16LE(deflate ? 8 : 0, 10);
    dir.writeUInt32LE(crc, 16);
    dir.writeUInt32LE(packed.length, 20);
    dir.writeUInt32LE(size, 24);
    dir.writeUInt16LE(nameBytes.length, 28);
    dir.writeUInt32LE(offset, 42);
    locals.push(local, nameBytes, packed);
    central.push(dir, nameBytes);
    offset += 30 + nameBytes.length + packed.length;
  }
  const dirBytes = Buffer.concat(central);
  const end = Buffer.alloc(22);
  end.writeUInt32LE(0x06054b50, 0);
  end.writeUInt16LE(entries.length, 8);
  end.writeUInt16LE(entries.length, 10);
  end.writeUInt32LE(dirBytes.length, 12);
  end.writeUInt32LE(offset, 16);
  return Buffer.concat([...locals, dirBytes, end]);
}

/** Drops `paths` (files or folders on disk) on the middle of the view, as a drag from the desktop does. */
export async function dropPaths(page, paths) {
  const box = await page.locator('#view').boundingBox();
  const at = { x: Math.round(box.x + box.width / 2), y: Math.round(box.y + box.height / 2) };
  const cdp = await page.context().newCDPSession(page);
  const data = { items: [], files: paths, dragOperationsMask: 1 };
  for (const type of ['dragEnter', 'dragOver', 'drop']) {
    await cdp.send('Input.dispatchDragEvent', { type, ...at, data });
  }
  await cdp.detach();
}

/** The status line once it reports the URDF at `urdfPath` loaded. */
export async function loaded(page, urdfPath) {
  const escaped = urdfPath.replace(/[.*+?^${}()|[\]\\]/g, '\\$&');
  const status = page.locator('#status').filter({ hasText: new RegExp(`Loaded URDF ${escaped}\\.`) });
  await status.waitFor({ timeout: 60000 });
  return status.innerText();
}

/** A screenshot of the view after a few frames, decoded. */
export async function shot(page, name) {
  await frames(page, 3);
  const file = path.join(artifacts, name);
  const box = await page.locator('#view').boundingBox();
  await page.screenshot({ path: file, clip: box });
  return decodePng(fs.readFileSync(file));
}

/** Pixels (every other row and column) whose colours differ by more than 30. */
export function differing(a, b) {
  let n = 0;
  for (let y = 0; y < a.height; y += 2) {
    for (let x = 0; x < a.width; x += 2) {
      if (colourDistance(pixel(a, x, y), pixel(b, x, y)) > 30) n += 1;
    }
  }
  return n;
}

/** Sets the meshes / volumes toggles. */
export async function display(page, { meshes, volumes }) {
  for (const [id, on] of [['#show-meshes', meshes], ['#show-volumes', volumes]]) {
    if ((await page.locator(id).isChecked()) !== on) await page.locator(id).click();
  }
}
