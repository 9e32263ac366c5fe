#!/usr/bin/env python3
"""Reference dynamics for crate/tests/dynamics_pinocchio.rs, computed by Pinocchio.

How to run (from the repository root; needs Python 3.10+ and PyPI):

    python3 -m venv /tmp/pinvenv
    /tmp/pinvenv/bin/pip install pin==4.1.0
    /tmp/pinvenv/bin/python crate/tests/data/dynamics/generate.py

It writes, beside this script, `random_chain.urdf` (a made-up chain with
revolute and prismatic joints, arbitrary axes and frames, and fixed links
carrying mass) and one `<robot>.json` per robot. The output is deterministic
for a given Pinocchio and NumPy (seeded generator).

For each robot the URDF is first cut down to what the crate imports: the
joints on the path from `base` to `tip`, and every link hung from a link of
that path (or from the base) by fixed joints, recursively. Everything else
(fingers, other arms, the head, mimic joints) is dropped from the model, so
that both sides describe the same bodies. Pinocchio lumps the fixed links
into the moving body they ride on, as the crate does.

Each JSON holds the joint names in the order of q, the kept links, the
gravity vector (world = the base link's frame) and SAMPLES states with
q within the joint limits (continuous joints: [-pi, pi]), qdot within the
velocity limits, qddot within +-ACCELERATION, and Pinocchio's
tau = rnea(q, qdot, qddot), M = crba(q) (symmetrised), g = gravity torques
and nle = C(q, qdot) qdot + g.
"""

import json
import math
import os
import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin

HERE = os.path.dirname(os.path.abspath(__file__))
URDF_DIR = os.path.join(HERE, "..", "urdf")
SAMPLES = 10
ACCELERATION = 5.0
SEED = 20261128

ROBOTS = [
    # name, URDF (relative to crate/tests/data/urdf), base link, tip link
    ("panda", "panda_collision.urdf", "panda_link0", "panda_hand"),
    ("ur5", "ur5_robot.urdf", "world", "tool0"),
    ("iiwa14", "iiwa14_primitive_collision.urdf", "base", "iiwa_link_ee"),
    ("pr2_right_arm", "pr2.urdf", "base_footprint", "r_gripper_palm_link"),
    ("random_chain", "../dynamics/random_chain.urdf", "base", "tip"),
]


def prune(xml_text, base, tip):
    """The URDF reduced to the base-to-tip path and the links fixed to it."""
    root = ET.fromstring(xml_text)
    joints = root.findall("joint")
    links = {l.get("name"): l for l in root.findall("link")}
    parent_joint = {j.find("child").get("link"): j for j in joints}
    path = []
    link = tip
    while link != base:
        j = parent_joint[link]
        path.append(j)
        link = j.find("parent").get("link")
    path.reverse()
    kept = [base] + [j.find("child").get("link") for j in path]
    kept_joints = list(path)
    queue = list(kept)
    while queue:
        link = queue.pop(0)
        for j in joints:
            if j.get("type") != "fixed" or j in kept_joints:
                continue
            if j.find("parent").get("link") == link:
                child = j.find("child").get("link")
                if child not in kept:
                    kept.append(child)
                    kept_joints.append(j)
                    queue.append(child)
    out = ET.Element("robot", {"name": root.get("name", "robot")})
    for name in kept:
        out.append(links[name])
    for j in kept_joints:
        out.append(j)
    names = [j.get("name") for j in path if j.get("type") != "fixed"]
    return ET.tostring(out, encoding="unicode"), names, kept


def fmt(v):
    return " ".join(repr(float(x)) for x in v)


def random_rotation(rng):
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def random_inertial(rng):
    mass = rng.uniform(0.2, 5.0)
    # Principal moments from a random box-like body: they satisfy the
    # triangle inequality.
    s = rng.uniform(0.02, 0.3, size=3) ** 2 * mass / 12.0
    principal = np.array([s[1] + s[2], s[0] + s[2], s[0] + s[1]])
    r = random_rotation(rng)
    inertia = r @ np.diag(principal) @ r.T
    com = rng.uniform(-0.15, 0.15, size=3)
    rpy = rng.uniform(-math.pi, math.pi, size=3)
    # The inertia is given in a frame turned by rpy: the crate must apply it.
    return (
        f'<inertial><origin xyz="{fmt(com)}" rpy="{fmt(rpy)}"/>'
        f'<mass value="{float(mass)!r}"/>'
        f'<inertia ixx="{float(inertia[0, 0])!r}" ixy="{float(inertia[0, 1])!r}" '
        f'ixz="{float(inertia[0, 2])!r}" iyy="{float(inertia[1, 1])!r}" '
        f'iyz="{float(inertia[1, 2])!r}" izz="{float(inertia[2, 2])!r}"/></inertial>'
    )


def random_chain(rng):
    """A 7-joint chain: revolute and prismatic joints about random axes,
    random joint origins, fixed links with mass inside and at the end."""
    kinds = ["revolute", "prismatic", "revolute", "revolute", "fixed",
             "prismatic", "revolute", "revolute", "fixed"]
    parts = ['<robot name="random_chain">', '<link name="base">' + random_inertial(rng) + "</link>"]
    parent = "base"
    for k, kind in enumerate(kinds):
        child = "tip" if k == len(kinds) - 1 else f"link{k + 1}"
        parts.append(f'<link name="{child}">{random_inertial(rng)}</link>')
        xyz = rng.uniform(-0.3, 0.3, size=3)
        rpy = rng.uniform(-math.pi, math.pi, size=3)
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        joint = (
            f'<joint name="j{k + 1}" type="{kind}"><parent link="{parent}"/>'
            f'<child link="{child}"/><origin xyz="{fmt(xyz)}" rpy="{fmt(rpy)}"/>'
        )
        if kind == "revolute":
            joint += f'<axis xyz="{fmt(axis)}"/><limit lower="-2.5" upper="2.5" effort="100" velocity="2"/>'
        elif kind == "prismatic":
            joint += f'<axis xyz="{fmt(axis)}"/><limit lower="-0.4" upper="0.4" effort="500" velocity="0.5"/>'
        parts.append(joint + "</joint>")
        parent = child
    parts.append("</robot>")
    return "\n".join(parts) + "\n"


def state(model, rng):
    """A random (q, qdot, qddot) in Pinocchio's layout and as angles."""
    q = pin.neutral(model)
    angles, qdot, qddot = [], [], []
    for j in model.joints[1:]:
        lo, hi = model.lowerPositionLimit[j.idx_q], model.upperPositionLimit[j.idx_q]
        if j.nq == 2:  # continuous: (cos, sin)
            a = rng.uniform(-math.pi, math.pi)
            q[j.idx_q], q[j.idx_q + 1] = math.cos(a), math.sin(a)
        else:
            a = rng.uniform(lo, hi)
            q[j.idx_q] = a
        angles.append(a)
        vmax = model.velocityLimit[j.idx_v]
        vmax = vmax if 0 < vmax < 1e3 else 2.0
        qdot.append(rng.uniform(-vmax, vmax))
        qddot.append(rng.uniform(-ACCELERATION, ACCELERATION))
    return q, np.array(angles), np.array(qdot), np.array(qddot)


def fixture(name, urdf, base, tip, rng):
    with open(os.path.join(URDF_DIR, urdf)) as f:
        text = f.read()
    pruned, joint_names, kept = prune(text, base, tip)
    model = pin.buildModelFromXML(pruned)
    assert [model.names[i] for i in range(1, model.njoints)] == joint_names, name
    assert model.nv == len(joint_names)
    # urdfdom reports unreadable inertials on stderr and goes on: refuse a
    # model whose moving bodies have no mass.
    assert all(model.inertias[i].mass > 0 for i in range(1, model.njoints)), name
    data = model.createData()
    samples = []
    for _ in range(SAMPLES):
        q, angles, qdot, qddot = state(model, rng)
        tau = pin.rnea(model, data, q, qdot, qddot).copy()
        m = pin.crba(model, data, q).copy()
        m = np.triu(m) + np.triu(m, 1).T
        g = pin.computeGeneralizedGravity(model, data, q).copy()
        nle = pin.nonLinearEffects(model, data, q, qdot).copy()
        samples.append(
            {
                "q": angles.tolist(),
                "qdot": qdot.tolist(),
                "qddot": qddot.tolist(),
                "tau": tau.tolist(),
                "mass_matrix": m.tolist(),
                "gravity_torque": g.tolist(),
                "nonlinear_effects": nle.tolist(),
            }
        )
    return {
        "robot": name,
        "urdf": urdf,
        "base": base,
        "tip": tip,
        "generator": f"Pinocchio {pin.__version__} (pip package pin), NumPy {np.__version__}",
        "joint_names": joint_names,
        "links": kept,
        "gravity": [float(x) for x in model.gravity.linear],
        "samples": samples,
    }


def main():
    rng = np.random.default_rng(SEED)
    with open(os.path.join(HERE, "random_chain.urdf"), "w") as f:
        f.write(random_chain(rng))
    for name, urdf, base, tip in ROBOTS:
        out = fixture(name, urdf, base, tip, rng)
        with open(os.path.join(HERE, f"{name}.json"), "w") as f:
            json.dump(out, f, indent=1)
            f.write("\n")
        print(name, len(out["joint_names"]), "joints,", len(out["links"]), "links")


if __name__ == "__main__":
    main()
