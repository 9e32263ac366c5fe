#!/usr/bin/env python3
"""Independent goal poses of NEO's 198 PR2 problems.

Run from the repository root (Python 3.8+, numpy):

    python3 crate/tests/data/neo/pr2_goal_poses.py

It reads crate/tests/data/urdf/pr2.urdf and crate/tests/data/neo/pr2-scenes.json
and writes crate/tests/data/neo/pr2_goal_poses.json (pass --check to compare
with the file on disk instead of writing it; exit status 1 on a difference).

For every problem (scene order, then the scene's `problems` order; the names
are those of reach::pr2_problems, `pr2/<scene>/<k>`) it gives the pose of
`r_wrist_roll_link` in `base_footprint` at the goal configuration: the URDF
chain base_footprint -> base_footprint_joint -> base_link -> torso_lift_joint
(prismatic, at the scene's torso_lift, 0.16825 m) -> torso_lift_link ->
r_shoulder_pan_joint ... r_wrist_roll_joint, every joint origin composed
(xyz, then rpy as R = Rz(yaw) Ry(pitch) Rx(roll)), each moving joint's motion
about/along its axis after its origin. Nothing of the crate is used: the
XML is read with xml.etree and the transforms are numpy 4x4 matrices.

The fixture also records, per problem, how far this pose is from the one
obtained when the base pose of the arm imported from torso_lift_link is
replaced by the torso pose instead of composed with the shoulder origin
(the chain then starts at r_shoulder_pan_joint with its origin dropped).
"""

import hashlib
import json
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[4]
URDF = ROOT / "crate/tests/data/urdf/pr2.urdf"
SCENES = ROOT / "crate/tests/data/neo/pr2-scenes.json"
OUT = ROOT / "crate/tests/data/neo/pr2_goal_poses.json"
FRAME = "base_footprint"
TIP = "r_wrist_roll_link"


def floats(text, default):
    return [float(v) for v in text.split()] if text else list(default)


def rpy_matrix(roll, pitch, yaw):
    cr, sr = np.cos(roll), np.sin(roll)
    cp, sp = np.cos(pitch), np.sin(pitch)
    cy, sy = np.cos(yaw), np.sin(yaw)
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    rz = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    return rz @ ry @ rx


def axis_angle(axis, angle):
    k = np.asarray(axis, dtype=float)
    k = k / np.linalg.norm(k)
    skew = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(angle) * skew + (1.0 - np.cos(angle)) * (skew @ skew)


def homogeneous(rotation, translation):
    t = np.eye(4)
    t[:3, :3] = rotation
    t[:3, 3] = translation
    return t


class Joint:
    def __init__(self, element):
        self.name = element.get("name")
        self.kind = element.get("type")
        self.parent = element.find("parent").get("link")
        self.child = element.find("child").get("link")
        origin = element.find("origin")
        xyz = floats(origin.get("xyz") if origin is not None else None, (0, 0, 0))
        rpy = floats(origin.get("rpy") if origin is not None else None, (0, 0, 0))
        self.origin = homogeneous(rpy_matrix(*rpy), xyz)
        axis = element.find("axis")
        self.axis = floats(axis.get("xyz") if axis is not None else None, (1, 0, 0))

    def motion(self, value):
        if self.kind in ("revolute", "continuous"):
            return homogeneous(axis_angle(self.axis, value), (0, 0, 0))
        if self.kind == "prismatic":
            k = np.asarray(self.axis, dtype=float)
            return homogeneous(np.eye(3), value * k / np.linalg.norm(k))
        if self.kind == "fixed":
            return np.eye(4)
        raise ValueError(f"joint {self.name}: unsupported type {self.kind}")


def chain(joints, base, tip):
    """Joints from base down to tip (each link has one parent joint)."""
    by_child = {j.child: j for j in joints}
    out = []
    link = tip
    while link != base:
        if link not in by_child:
            raise ValueError(f"{tip} is not below {base}")
        joint = by_child[link]
        out.append(joint)
        link = joint.parent
    return out[::-1]


def pose(path, values):
    t = np.eye(4)
    for joint in path:
        t = t @ joint.origin @ joint.motion(values.get(joint.name, 0.0))
    return t


def quaternion(r):
    """[x, y, z, w] with w >= 0 (Shepperd's method)."""
    trace = np.trace(r)
    if trace > 0:
        s = 2.0 * np.sqrt(1.0 + trace)
        q = [(r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, 0.25 * s]
    else:
        i = int(np.argmax(np.diag(r)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * np.sqrt(1.0 + r[i, i] - r[j, j] - r[k, k])
        q = [0.0, 0.0, 0.0, (r[k, j] - r[j, k]) / s]
        q[i] = 0.25 * s
        q[j] = (r[j, i] + r[i, j]) / s
        q[k] = (r[k, i] + r[i, k]) / s
    q = np.array(q)
    q = q / np.linalg.norm(q)
    return -q if q[3] < 0 else q


def rotation_angle(a, b):
    d = a.T @ b
    s = np.linalg.norm([d[2, 1] - d[1, 2], d[0, 2] - d[2, 0], d[1, 0] - d[0, 1]])
    return float(np.arctan2(s, np.trace(d) - 1.0))


def build():
    urdf_bytes = URDF.read_bytes()
    scenes_bytes = SCENES.read_bytes()
    root = ET.fromstring(urdf_bytes)
    joints = [Joint(e) for e in root.findall("joint")]
    path = chain(joints, FRAME, TIP)
    names = [j.name for j in path]
    data = json.loads(scenes_bytes)
    arm = data["arm"]["joints"]
    torso_joint = data["arm"]["torso_joint"]
    shoulder = names.index(arm[0])
    torso = path[: shoulder]
    arm_path = path[shoulder:]

    problems = []
    shift_max = [0.0, 0.0]
    check_max = [0.0, 0.0]
    for scene in data["scenes"]:
        torso_values = {torso_joint: scene["torso_lift"]}
        torso_pose = pose(torso, torso_values)
        for k, p in enumerate(scene["problems"]):
            values = dict(torso_values)
            values.update(zip(arm, p["goal"]))
            t = pose(path, values)
            # The base pose replaced by the torso pose: the shoulder origin is lost.
            replaced = torso_pose @ np.linalg.inv(arm_path[0].origin) @ pose(arm_path, values)
            shift = replaced[:3, 3] - t[:3, 3]
            shift_max[0] = max(shift_max[0], float(np.linalg.norm(shift)))
            shift_max[1] = max(shift_max[1], rotation_angle(replaced[:3, :3], t[:3, :3]))
            listed = p.get("goalPose_" + TIP)
            if listed is not None:
                lr = listed["rotation"]
                lq = np.array(lr) / np.linalg.norm(lr)
                check_max[0] = max(check_max[0], float(np.max(np.abs(np.array(listed["position"]) - t[:3, 3]))))
                mine = quaternion(t[:3, :3])
                dot = abs(float(lq @ mine))
                gap = float(np.linalg.norm(np.cross(lq[:3], mine[:3]) + lq[3] * mine[:3] - mine[3] * lq[:3]))
                check_max[1] = max(check_max[1], 2.0 * float(np.arctan2(gap, dot)))
            problems.append({
                "name": f"pr2/{scene['name']}/{k}",
                "startIndex": p.get("startIndex"),
                "goalIndex": p.get("goalIndex"),
                "goal": p["goal"],
                "position": t[:3, 3].tolist(),
                "rotation": quaternion(t[:3, :3]).tolist(),
                "matrix": t[:3, :3].tolist(),
                "replacedBaseShift": shift.tolist(),
            })

    return {
        "description": (
            "Pose of r_wrist_roll_link in base_footprint at each problem's goal configuration, "
            "from pr2.urdf alone (torso composed with the shoulder origin). Written by "
            "pr2_goal_poses.py beside this file; regenerate with "
            "`python3 crate/tests/data/neo/pr2_goal_poses.py` from the repository root."
        ),
        "urdf": "crate/tests/data/urdf/pr2.urdf",
        "urdf_sha256": hashlib.sha256(urdf_bytes).hexdigest(),
        "scenes": "crate/tests/data/neo/pr2-scenes.json",
        "scenes_sha256": hashlib.sha256(scenes_bytes).hexdigest(),
        "frame": FRAME,
        "link": TIP,
        "torso_joint": torso_joint,
        "torso_lift": sorted({s["torso_lift"] for s in data["scenes"]}),
        "arm_joints": arm,
        "chain": names,
        "units": "m, rad",
        "rotation": "unit quaternion [x, y, z, w] with w >= 0; matrix: the same rotation, row-major 3x3",
        "replacedBaseShift": (
            "position of the flange when the imported arm's base pose (the shoulder origin in "
            "torso_lift_link) is replaced by the torso pose, minus the composed position, in base_footprint"
        ),
        "summary": {
            "problems": len(problems),
            "replacedBase_max_position_shift_m": shift_max[0],
            "replacedBase_max_rotation_shift_rad": shift_max[1],
            "pr2_scenes_goalPose_max_position_difference_m": check_max[0],
            "pr2_scenes_goalPose_max_rotation_difference_rad": check_max[1],
        },
        "problems": problems,
    }


def dumps(fixture):
    """Indented header, one problem per line."""
    problems = fixture.pop("problems")
    head = json.dumps(fixture, indent=1)[:-2]
    rows = ",\n  ".join(json.dumps(p) for p in problems)
    return head + ',\n "problems": [\n  ' + rows + "\n ]\n}\n"


def main():
    text = dumps(build())
    if "--check" in sys.argv[1:]:
        same = OUT.exists() and OUT.read_text() == text
        print("pr2_goal_poses.json is up to date" if same else "pr2_goal_poses.json differs")
        return 0 if same else 1
    OUT.write_text(text)
    print(f"wrote {OUT.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
