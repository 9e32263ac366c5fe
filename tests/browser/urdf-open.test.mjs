// Opening a robot from its URDF folder or zip in the playground (the UR5 of
// crate/tests/data, licences there), at 1280×800:
// - a folder dropped on the view (a real drop: the browser walks it as a
//   directory entry) shows the robot with its meshes drawn — pixels that go
//   when the meshes are switched off — on WebGPU and on WebGL2; the same
//   folder through the Folder… picker; a zip dropped on the view;
// - hostile input: a truncated STL, one with a NaN vertex, one declaring
//   4 294 967 295 triangles, a zip bomb (an entry declaring 4 KiB that
//   inflates past the 32 MiB cap) and a zip entry whose path climbs out of
//   the folder (`../upperarm.stl`): each is named with its reason, nothing is
//   loaded from it (its link has no fitted body), the rest of the robot
//   loads, and the page keeps drawing frames and answering input.
//
// Screenshots go to tests/artifacts/ (git-ignored): look at them.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { serve } from '../../scripts/serve.mjs';
import { launch, collectErrors, frames, artifacts } from './chromium.mjs';
import {
  UR5_PARTS, ur5Urdf, ur5Mesh, ur5Folder, tempRoot, zip, dropPaths, loaded, shot, differing, display,
} from './urdf-kit.mjs';

let server;
let baseUrl;
let root;

before(async () => {
  fs.mkdirSync(artifacts, { recursive: true });
  ({ server, url: baseUrl } = await serve({ port: 0 }));
  root = tempRoot();
});
after(async () => {
  fs.rmSync(root, { recursive: true, force: true });
  await new Promise((resolve) => server.close(resolve));
});

async function open(browser, backend) {
  const page = await browser.context.newPage();
  const errors = collectErrors(page);
  await page.goto(`${baseUrl}?scenario=lwr4-elbow&paused&backend=${backend}`);
  await page.evaluate(() => window.playground.ready);
  assert.equal((await page.evaluate(() => window.playground.state())).backend, backend);
  return { page, errors };
}

/** Names of the links the loaded URDF's volumes were fitted to. */
const fittedBodies = (page) => page.evaluate(() => window.playground.app.urdfReport.after.bodies.map((b) => b.name));

/** Meshes drawn: pixels that change when the meshes are switched off (volumes off). */
async function meshPixels(page, name) {
  await display(page, { meshes: true, volumes: false });
  const meshes = await shot(page, `${name}-meshes.png`);
  await display(page, { meshes: false, volumes: false });
  const neither = await shot(page, `${name}-neither.png`);
  await display(page, { meshes: true, volumes: true });
  return differing(meshes, neither);
}

/** The page still draws frames and answers a click (the volumes toggle flips and back). */
async function responsive(page) {
  await frames(page, 3);
  const on = await page.locator('#show-volumes').isChecked();
  await page.locator('#show-volumes').click();
  assert.equal(await page.locator('#show-volumes').isChecked(), !on);
  await page.locator('#show-volumes').click();
  await frames(page, 2);
}

for (const backend of ['webgpu', 'webgl2']) {
  test(`a URDF folder dropped on the view shows the robot with its meshes (${backend})`, async () => {
    const browser = await launch({ webgpu: backend === 'webgpu', viewport: { width: 1280, height: 800 } });
    try {
      const { page, errors } = await open(browser, backend);
      const before = await page.evaluate(() => window.playground.app.robotSpec.joints.length);
      assert.equal(before, 7, 'the LWR4 before the drop');
      await dropPaths(page, [ur5Folder(root, `ur5-drop-${backend}`)]);
      const status = await loaded(page, `ur5-drop-${backend}/urdf/ur5_robot.urdf`);
      assert.match(status, /Volumes fitted to 6 collision meshes: vertices inside [\d.]+ % → 100\.0 %/);
      assert.equal(await page.evaluate(() => window.playground.app.robotSpec.joints.length), 6);
      assert.equal(await page.locator('#error').isVisible(), false, 'nothing to report');
      const n = await meshPixels(page, `urdf-drop-folder-${backend}`);
      assert.ok(n > 2000, `mesh pixels: ${n}`);
      await shot(page, `urdf-drop-folder-${backend}.png`);
      assert.deepEqual(errors, []);
    } finally {
      await browser.close();
    }
  });
}

test('the same folder through the Folder… picker, and a zip dropped on the view', async () => {
  const browser = await launch({ webgpu: false, viewport: { width: 1280, height: 800 } });
  try {
    const { page, errors } = await open(browser, 'webgl2');
    await page.locator('#urdf-folder').setInputFiles(ur5Folder(root, 'ur5-picked'));
    await loaded(page, 'ur5-picked/urdf/ur5_robot.urdf');
    assert.equal((await fittedBodies(page)).length, 6);
    const picked = await meshPixels(page, 'urdf-picked-folder');
    assert.ok(picked > 2000, `mesh pixels (picker): ${picked}`);

    // A zip of the package (meshes deflated, the URDF stored).
    const file = path.join(root, 'ur5.zip');
    fs.writeFileSync(file, zip([
      { name: 'ur5-zip/urdf/ur5_robot.urdf', bytes: ur5Urdf() },
      ...UR5_PARTS.map((p) => ({ name: `ur5-zip/meshes/ur5/collision/${p}.stl`, bytes: ur5Mesh(p), deflate: true })),
    ]));
    await dropPaths(page, [file]);
    const status = await loaded(page, 'ur5-zip/urdf/ur5_robot.urdf');
    assert.match(status, /Volumes fitted to 6 collision meshes/);
    const zipped = await meshPixels(page, 'urdf-drop-zip');
    assert.ok(zipped > 2000, `mesh pixels (zip): ${zipped}`);
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
  }
});

/** The UR5's upper arm (binary STL) with its count field set to `n`. */
function declaring(n) {
  const b = Buffer.from(ur5Mesh('upperarm'));
  b.writeUInt32LE(n, 80);
  return b;
}

test('hostile meshes and zips: named, nothing loaded from them, the page responsive', async () => {
  const browser = await launch({ webgpu: false, viewport: { width: 1280, height: 800 } });
  try {
    const { page, errors } = await open(browser, 'webgl2');
    const errorText = () => page.locator('#error').innerText();

    // Three broken meshes in one folder: the upper arm declares 2³²−1
    // triangles, the forearm is cut mid-triangle, wrist 1 has a NaN vertex.
    const forearm = ur5Mesh('forearm');
    const wrist1 = Buffer.from(ur5Mesh('wrist1'));
    wrist1.writeFloatLE(Number.NaN, 84 + 12 + 4);
    await dropPaths(page, [ur5Folder(root, 'ur5-broken', {
      upperarm: declaring(0xffffffff),
      forearm: forearm.subarray(0, 84 + 50 * 100 + 17),
      wrist1,
    })]);
    await loaded(page, 'ur5-broken/urdf/ur5_robot.urdf');
    let message = await errorText();
    assert.match(message, /upperarm\.stl": 4294967295 triangles is more than the 1000000 a mesh may have/);
    assert.match(message, new RegExp(`forearm\\.stl": declares ${forearm.readUInt32LE(80)} triangles \\(\\d+ bytes\\) but has ${84 + 50 * 100 + 17} bytes: truncated`));
    assert.match(message, /wrist1\.stl": vertex 0 is not a finite point/);
    assert.deepEqual(await fittedBodies(page), ['shoulder_link', 'wrist_2_link', 'wrist_3_link']);
    await shot(page, 'urdf-hostile-meshes.png');
    await responsive(page);

    // A zip bomb: the upper arm's entry declares 4 KiB and inflates to
    // 64 MiB (past the 32 MiB cap per file); unpacking stops at the cap.
    const bomb = path.join(root, 'bomb.zip');
    fs.writeFileSync(bomb, zip([
      { name: 'ur5-bomb/urdf/ur5_robot.urdf', bytes: ur5Urdf() },
      ...UR5_PARTS.filter((p) => p !== 'upperarm').map((p) => ({ name: `ur5-bomb/meshes/ur5/collision/${p}.stl`, bytes: ur5Mesh(p) })),
      { name: 'ur5-bomb/meshes/ur5/collision/upperarm.stl', bytes: Buffer.alloc(64 << 20), deflate: true, declared: 4096 },
    ]));
    assert.ok(fs.statSync(bomb).size < 400 << 10, `the bomb is small: ${fs.statSync(bomb).size} bytes`);
    await dropPaths(page, [bomb]);
    await loaded(page, 'ur5-bomb/urdf/ur5_robot.urdf');
    message = await errorText();
    assert.match(message, /bomb\.zip: "ur5-bomb\/meshes\/ur5\/collision\/upperarm\.stl": unpacks to more than 33554432 bytes/);
    assert.ok(!(await fittedBodies(page)).includes('upper_arm_link'), 'nothing from the bomb');
    assert.equal((await fittedBodies(page)).length, 5);
    await responsive(page);

    // An entry whose path climbs out of the folder: skipped and named; the
    // URDF's upper arm is then missing, and named too.
    const escape = path.join(root, 'escape.zip');
    fs.writeFileSync(escape, zip([
      { name: 'ur5-escape/urdf/ur5_robot.urdf', bytes: ur5Urdf() },
      ...UR5_PARTS.filter((p) => p !== 'upperarm').map((p) => ({ name: `ur5-escape/meshes/ur5/collision/${p}.stl`, bytes: ur5Mesh(p) })),
      { name: '../upperarm.stl', bytes: ur5Mesh('upperarm') },
      { name: '/etc/upperarm.stl', bytes: ur5Mesh('upperarm') },
    ]));
    await dropPaths(page, [escape]);
    await loaded(page, 'ur5-escape/urdf/ur5_robot.urdf');
    message = await errorText();
    assert.match(message, /escape\.zip: "\.\.\/upperarm\.stl" leads outside the folder; skipped/);
    assert.match(message, /escape\.zip: "\/etc\/upperarm\.stl" leads outside the folder; skipped/);
    assert.match(message, /upperarm\.stl" was not found/);
    assert.ok(!(await fittedBodies(page)).includes('upper_arm_link'), 'nothing from outside the folder');
    await shot(page, 'urdf-hostile-zip.png');
    await responsive(page);
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
  }
});
