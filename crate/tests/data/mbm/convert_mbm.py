#!/usr/bin/env python3
"""MotionBenchMaker's Panda problems as one compact JSON per scene.

Run from the repository root (Python 3.8+, numpy, PyYAML):

    python3 crate/tests/data/mbm/convert_mbm.py PROBLEMS_TAR_BZ2

PROBLEMS_TAR_BZ2 is `resources/panda/problems.tar.bz2` of KavrakiLab/vamp
(commit f6de6a72e0725ba08e0829f0a34261a3f465aed7, git blob
0bafc0bcaf92e372d425f5f52e16db1f34bec4a7, sha256 in SOURCE_SHA256 below):
MotionBenchMaker's output for the Panda, 7 scenes x 100 problems, each a
MoveIt planning scene (`sceneNNNN.yaml`) and motion plan request
(`requestNNNN.yaml`). The script reads the archive directly and writes
crate/tests/data/mbm/<scene>.json (see README.md beside it for the format).
Pass --check to compare with the files on disk instead of writing them.

The goal pose of panda_link8 (the flange) at each goal configuration is
computed from crate/tests/data/urdf/panda_collision.urdf with the URDF chain
of ../neo/pr2_goal_poses.py.
"""

import hashlib
import importlib.util
import json
import re
import sys
import tarfile
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[4]
OUT = ROOT / "crate/tests/data/mbm"
URDF = ROOT / "crate/tests/data/urdf/panda_collision.urdf"
SOURCE_SHA256 = "4e1509e99c53da769ee6a338cf1173ecf601e4ec16f24081d3894ef358243b69"
JOINTS = [f"panda_joint{i}" for i in range(1, 8)]
FINGERS = ["panda_finger_joint1", "panda_finger_joint2"]
FLANGE = "panda_link8"
LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
# The point between the Panda's fingertips, 0.1034 m along panda_link8's z:
# franka_description's panda_hand_tcp, 0.1034 m beyond panda_hand, whose
# origin is panda_link8's (turned 45 degrees about z).
GRASP_POINT = 0.1034


def urdf_chain():
    spec = importlib.util.spec_from_file_location(
        "pr2_goal_poses", ROOT / "crate/tests/data/neo/pr2_goal_poses.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    joints = [module.Joint(e) for e in ET.fromstring(URDF.read_bytes()).findall("joint")]
    return module, module.chain(joints, "panda_link0", FLANGE)


def quaternion_matrix(q):
    x, y, z, w = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def identity_transform(t):
    return list(t["translation"]) == [0, 0, 0] and list(t["rotation"]) == [0, 0, 0, 1]


def joint_values(state, names):
    by_name = dict(zip(state["name"], state["position"]))
    return [by_name[n] for n in names]


def obstacle(obj, notes):
    """One collision object (one primitive, as in every MBM file) in the base frame."""
    if set(obj) != {"id", "primitives", "primitive_poses"} or len(obj["primitives"]) != 1:
        raise ValueError(f"object {obj.get('id')}: unexpected layout {sorted(obj)}")
    prim, pose = obj["primitives"][0], obj["primitive_poses"][0]
    centre, rotation = list(pose["position"]), list(pose["orientation"])
    norm = float(np.linalg.norm(rotation))
    notes["max_quaternion_norm_error"] = max(notes["max_quaternion_norm_error"], abs(norm - 1.0))
    dims = prim["dimensions"]
    if prim["type"] == "box":
        return "boxes", {"id": obj["id"], "center": centre,
                         "halfExtents": [d / 2 for d in dims], "rotation": rotation}
    if prim["type"] == "cylinder":
        # shape_msgs/SolidPrimitive: dimensions [height, radius], axis = local z.
        height, radius = dims
        axis = quaternion_matrix(rotation)[:, 2] * (height / 2)
        c = np.array(centre)
        return "cylinders", {"id": obj["id"], "center": centre, "rotation": rotation,
                             "radius": radius, "halfLength": height / 2,
                             "a": (c - axis).tolist(), "b": (c + axis).tolist()}
    if prim["type"] == "sphere":
        return "spheres", {"id": obj["id"], "center": centre, "radius": dims[0]}
    raise ValueError(f"object {obj['id']}: primitive {prim['type']} not converted")


def signed_distance(point, kind, shape):
    """Signed distance from `point` to a converted box or cylinder (< 0 inside)."""
    p = np.asarray(point, dtype=float)
    if kind == "boxes":
        local = quaternion_matrix(shape["rotation"]).T @ (p - np.array(shape["center"]))
        d = np.abs(local) - np.array(shape["halfExtents"])
        return float(np.linalg.norm(np.maximum(d, 0.0)) + min(d.max(), 0.0))
    if kind == "cylinders":
        local = quaternion_matrix(shape["rotation"]).T @ (p - np.array(shape["center"]))
        d = np.array([np.hypot(local[0], local[1]) - shape["radius"],
                      abs(local[2]) - shape["halfLength"]])
        return float(np.linalg.norm(np.maximum(d, 0.0)) + min(d.max(), 0.0))
    return float(np.linalg.norm(p - np.array(shape["center"])) - shape["radius"])


def grasped_object(t, obstacles, where):
    """The object the hand grasps at the goal pose `t`.

    Every MotionBenchMaker goal is a grasp query (the scene's queries file names
    the object, e.g. `objects: ["Can1"]`, and an offset of the hand from it): at
    the goal the open fingers straddle that object (in `box` they close on the
    can's top from above: the grasp point is up to 2 mm above it). The script
    refuses a goal whose nearest object is farther than 1 cm from the grasp
    point, or whose second nearest is within 5 cm of it."""
    point = t[:3, 3] + t[:3, 2] * GRASP_POINT
    near = sorted((signed_distance(point, kind, s), s["id"])
                  for kind, shapes in obstacles.items() for s in shapes)
    if near[0][0] > 0.01 or (len(near) > 1 and near[1][0] < 0.05):
        raise ValueError(f"{where}: no single grasped object ({near[:2]})")
    return near[0][1]


def read_archive(path):
    """{scene directory: {index: {"scene": dict, "request": dict}}}."""
    out = {}
    with tarfile.open(path, "r:bz2") as tar:
        for member in tar.getmembers():
            m = re.fullmatch(r"(?:\./)?problems/(\w+)/(scene|request)(\d+)\.yaml", member.name)
            if not m or not member.isfile():
                continue
            doc = yaml.load(tar.extractfile(member).read(), Loader=LOADER)
            out.setdefault(m[1], {}).setdefault(int(m[3]), {})[m[2]] = doc
    return out


def limits_of():
    out = {}
    for j in ET.fromstring(URDF.read_bytes()).findall("joint"):
        lim = j.find("limit")
        if j.get("name") in JOINTS and lim is not None:
            out[j.get("name")] = (float(lim.get("lower")), float(lim.get("upper")))
    return [out[n] for n in JOINTS]


def convert_scene(name, problems, module, chain, limits, source):
    rows, fingers = [], set()
    notes = {"max_quaternion_norm_error": 0.0}
    at_limit = {"start": 0, "goal": 0}
    beyond_limit = {"start": 0, "goal": 0}
    starts = set()
    for index in sorted(problems):
        scene, request = problems[index]["scene"], problems[index]["request"]
        start_state = request["start_state"]
        for transforms in (scene["robot_state"]["multi_dof_joint_state"]["transforms"],
                           start_state["multi_dof_joint_state"]["transforms"],
                           [f["transform"] for f in scene["fixed_frame_transforms"]]):
            if not all(identity_transform(t) for t in transforms):
                raise ValueError(f"{name}/{index}: base not at the world origin")
        (goal,) = request["goal_constraints"]
        if set(goal) != {"joint_constraints"}:
            raise ValueError(f"{name}/{index}: goal is not a joint goal")
        goal_q = [dict((c["joint_name"], c["position"]) for c in goal["joint_constraints"])[n]
                  for n in JOINTS]
        start_q = joint_values(start_state["joint_state"], JOINTS)
        fingers.add(tuple(joint_values(start_state["joint_state"], FINGERS)))
        starts.add(tuple(start_q))
        for key, q in (("start", start_q), ("goal", goal_q)):
            if any(v < lo - 1e-12 or v > hi + 1e-12 for v, (lo, hi) in zip(q, limits)):
                beyond_limit[key] += 1
            elif any(abs(v - lo) < 1e-9 or abs(v - hi) < 1e-9 for v, (lo, hi) in zip(q, limits)):
                at_limit[key] += 1
        t = module.pose(chain, dict(zip(JOINTS, goal_q)))
        obstacles = {"boxes": [], "cylinders": [], "spheres": []}
        for obj in scene["world"]["collision_objects"]:
            kind, shape = obstacle(obj, notes)
            obstacles[kind].append(shape)
        rows.append({
            "name": f"mbm/{name}/{index}",
            "start": start_q,
            "goalQ": goal_q,
            "grasped": grasped_object(t, obstacles, f"{name}/{index}"),
            "goal": {"position": t[:3, 3].tolist(),
                     "rotation": module.quaternion(t[:3, :3]).tolist()},
            "obstacles": {k: v for k, v in obstacles.items() if v},
        })
    return {
        "set": "mbm",
        "scene": name,
        "source": source,
        "frame": "panda_link0 (MoveIt's world: the virtual joint, the scene's fixed frame "
                 "and the start state's multi-DOF transform are the identity in every file)",
        "units": "m, rad; quaternions [x, y, z, w] as in the source",
        "robot": {
            "joints": JOINTS,
            "fingers": {"joints": FINGERS, "values": sorted(fingers)[0] if len(fingers) == 1
                        else sorted(fingers),
                        "note": "MotionBenchMaker's Panda holds each finger 0.065 m from the hand "
                                "axis (a fixed joint in its URDF); the real limit is 0.04 m"},
        },
        "goal": f"goalQ from the request's joint constraints; goal = pose of {FLANGE} at goalQ "
                "(crate/tests/data/urdf/panda_collision.urdf); grasped = the id of the object "
                f"nearest to the grasp point ({GRASP_POINT} m along {FLANGE}'s z) at goalQ",
        "obstacles": "boxes {id, center, halfExtents, rotation}; cylinders {id, center, rotation, "
                     "radius, halfLength, a, b} (axis = local z, a and b its end centres); "
                     "spheres {id, center, radius}",
        "summary": {
            "problems": len(rows),
            "distinct_starts": len(starts),
            "objects_per_problem": sorted({sum(len(v) for v in r["obstacles"].values()) for r in rows}),
            "configurations_at_a_joint_limit": at_limit,
            "configurations_beyond_a_joint_limit": beyond_limit,
            "max_quaternion_norm_error": notes["max_quaternion_norm_error"],
        },
        "problems": rows,
    }


def dumps(doc):
    """Indented header, one problem per line."""
    rows = doc.pop("problems")
    head = json.dumps(doc, indent=1)[:-2]
    body = ",\n  ".join(json.dumps(r, separators=(",", ":")) for r in rows)
    return head + ',\n "problems": [\n  ' + body + "\n ]\n}\n"


def main(argv):
    args = [a for a in argv if not a.startswith("--")]
    if len(args) != 1:
        print(__doc__)
        return 2
    archive = Path(args[0])
    digest = hashlib.sha256(archive.read_bytes()).hexdigest()
    if digest != SOURCE_SHA256:
        print(f"warning: {archive} has sha256 {digest}, not the converted archive's")
    source = {
        "dataset": "MotionBenchMaker (Chamzas et al., IEEE RA-L 2022), Panda problems",
        "generator": "KavrakiLab/motion_bench_maker (BSD-3-Clause)",
        "archive": "KavrakiLab/vamp@f6de6a72e0725ba08e0829f0a34261a3f465aed7:"
                   "resources/panda/problems.tar.bz2 (Apache-2.0)",
        "archive_sha256": digest,
        "converted_by": "crate/tests/data/mbm/convert_mbm.py",
    }
    module, chain = urdf_chain()
    limits = limits_of()
    differ = []
    for directory, problems in sorted(read_archive(archive).items()):
        name = directory[: -len("_panda")] if directory.endswith("_panda") else directory
        source_scene = dict(source, directory=f"problems/{directory}/")
        text = dumps(convert_scene(name, problems, module, chain, limits, source_scene))
        path = OUT / f"{name}.json"
        if "--check" in argv:
            if not path.exists() or path.read_text() != text:
                differ.append(path.name)
        else:
            path.write_text(text)
            print(f"wrote {path.relative_to(ROOT)} ({len(problems)} problems)")
    if "--check" in argv:
        print("differ: " + ", ".join(differ) if differ else "all scenes up to date")
        return 1 if differ else 0
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
