// The presets drawn with their manufacturers' collision meshes: when the
// robot shown is a preset that has them (iiwa 14, Panda, UR5), its URDF and meshes are
// fetched once, lazily, from the folder the element's `preset-meshes`
// attribute names (the playground page: `robots/`, the files of
// crate/tests/data with their licences; `npm run build` copies them into
// dist/robots/ within a size budget, scripts/site.mjs), and drawn on the
// preset (`Viewer.setMeshesFromUrdf`: the URDF's tip must follow the
// preset's last frame). A folder that cannot be read leaves the volumes
// alone, with one line in the status.
//
// Owns: the fetched files per preset (`files`, fetched once) and the preset
// whose meshes are drawn (`shown`). Interface: `base` (the folder, or
// undefined for none), `sim` (the robot shown), `viewer()`, `messages`.

/** Per preset: its URDF, the URDF's tip at the preset's last frame, the licences, the mesh files (paths under the folder). */
export const PRESET_MESHES = {
  iiwa14: {
    urdf: 'urdf/iiwa14_mesh_collision.urdf',
    tip: 'iiwa_link_7',
    licences: ['meshes/iiwa14/LICENSE', 'urdf/iiwa_description.LICENSE', 'urdf/iiwa_stack.LICENSE'],
    meshes: ['link_0', 'link_1', 'link_2', 'link_3', 'link_4', 'link_5', 'link_6', 'link_7'].map((p) => `meshes/iiwa14/collision/${p}.stl`),
  },
  panda: {
    urdf: 'urdf/panda_mesh_collision.urdf',
    tip: 'panda_link8',
    licences: ['meshes/panda/LICENSE', 'urdf/panda_description.LICENSE'],
    meshes: ['link0', 'link1', 'link2', 'link3', 'link4', 'link5', 'link6', 'link7', 'hand'].map((p) => `meshes/panda/collision/${p}.stl`),
  },
  ur5: {
    urdf: 'urdf/ur5_robot.urdf',
    tip: 'ee_link',
    licences: ['meshes/ur5/LICENSE', 'urdf/example-robot-data.LICENSE'],
    meshes: ['base', 'shoulder', 'upperarm', 'forearm', 'wrist1', 'wrist2', 'wrist3'].map((p) => `meshes/ur5/collision/${p}.stl`),
  },
};

/** The preset a scenario's robot names (`'panda'`, `{ preset: 'panda' }`), or null. */
export function presetName(robot) {
  if (typeof robot === 'string') return robot;
  if (robot && typeof robot === 'object' && typeof robot.preset === 'string') return robot.preset;
  return null;
}

export class PresetMeshes {
  /**
   * @param {{ base: string|undefined, sim: import('./sim.js').Sim, viewer: () => any,
   *           messages: import('./messages.js').Messages }} host
   */
  constructor(host) {
    this.host = host;
    this.files = {};
    this.shown = null;
  }

  /** Draws the current preset's meshes (fetched on first use); nothing for other robots. */
  async show() {
    const { base, sim } = this.host;
    const name = presetName(sim.scenario?.robot);
    const entry = base && name ? PRESET_MESHES[name] : null;
    this.shown = null; // setRobot has just dropped any meshes
    if (!entry) return;
    const robotSpec = sim.robotSpec;
    try {
      this.files[name] ??= fetchPreset(new URL(base, document.baseURI), entry);
      const { xml, meshes } = await this.files[name];
      // Still the same robot (no other scene loaded meanwhile).
      const viewer = this.host.viewer();
      if (sim.robotSpec !== robotSpec || !viewer) return;
      viewer.setMeshesFromUrdf(xml, { tip: entry.tip, meshes });
      this.shown = name;
      sim.edited = true;
    } catch (err) {
      delete this.files[name];
      this.host.messages.status(`The ${name} meshes could not be drawn: ${err instanceof Error ? err.message : String(err)}`);
    }
  }
}

async function fetchPreset(base, entry) {
  const get = async (path) => {
    const r = await fetch(new URL(path, base));
    if (!r.ok) throw new Error(`${path}: HTTP ${r.status}`);
    return r;
  };
  const xml = await (await get(entry.urdf)).text();
  const meshes = Object.fromEntries(await Promise.all(entry.meshes.map(async (p) => [p, new Uint8Array(await (await get(p)).arrayBuffer())])));
  return { xml, meshes };
}
