#!/usr/bin/env python3
"""Per-subject segment lengths measured from each recording's own joints.

Reads every recording in this folder (CMU BVH, Kinect v2 CSV), computes the
world position of the joints per frame, and writes segment_lengths.json: for
each recording and segment the median length over frames (metres) with its
spread (5th and 95th percentile, median absolute deviation) and the number of
frames used. Only numpy is needed.  Run: python3 segment_lengths.py
"""
import json
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
# CMU's unit of length: (1/0.45) inch (see the CMU database's FAQ).
CMU_UNIT_M = 0.0254 / 0.45

KINECT2_JOINTS = [
    "SpineBase", "SpineMid", "Neck", "Head",
    "ShoulderLeft", "ElbowLeft", "WristLeft", "HandLeft",
    "ShoulderRight", "ElbowRight", "WristRight", "HandRight",
    "HipLeft", "KneeLeft", "AnkleLeft", "FootLeft",
    "HipRight", "KneeRight", "AnkleRight", "FootRight",
    "SpineShoulder", "HandTipLeft", "ThumbLeft", "HandTipRight", "ThumbRight",
]

# Segment name -> (from joint, to joint) per layout; "mid(a,b)" is a midpoint.
SEGMENTS = {
    "kinect2": {
        "upper_arm_left": ("ShoulderLeft", "ElbowLeft"),
        "upper_arm_right": ("ShoulderRight", "ElbowRight"),
        "forearm_left": ("ElbowLeft", "WristLeft"),
        "forearm_right": ("ElbowRight", "WristRight"),
        "hand_left": ("WristLeft", "HandTipLeft"),
        "hand_right": ("WristRight", "HandTipRight"),
        "thigh_left": ("HipLeft", "KneeLeft"),
        "thigh_right": ("HipRight", "KneeRight"),
        "shank_left": ("KneeLeft", "AnkleLeft"),
        "shank_right": ("KneeRight", "AnkleRight"),
        "foot_left": ("AnkleLeft", "FootLeft"),
        "foot_right": ("AnkleRight", "FootRight"),
        "trunk": ("mid(HipLeft,HipRight)", "mid(ShoulderLeft,ShoulderRight)"),
        "shoulder_width": ("ShoulderLeft", "ShoulderRight"),
        "hip_width": ("HipLeft", "HipRight"),
    },
    "cmu_bvh": {
        "upper_arm_left": ("LeftShoulder", "LeftElbow"),
        "upper_arm_right": ("RightShoulder", "RightElbow"),
        "forearm_left": ("LeftElbow", "LeftWrist"),
        "forearm_right": ("RightElbow", "RightWrist"),
        "hand_left": ("LeftWrist", "LFingers.end"),
        "hand_right": ("RightWrist", "RFingers.end"),
        "thigh_left": ("LeftHip", "LeftKnee"),
        "thigh_right": ("RightHip", "RightKnee"),
        "shank_left": ("LeftKnee", "LeftAnkle"),
        "shank_right": ("RightKnee", "RightAnkle"),
        "foot_left": ("LeftAnkle", "LeftToe.end"),
        "foot_right": ("RightAnkle", "RightToe.end"),
        "trunk": ("mid(LeftHip,RightHip)", "mid(LeftShoulder,RightShoulder)"),
        "shoulder_width": ("LeftShoulder", "RightShoulder"),
        "hip_width": ("LeftHip", "RightHip"),
    },
}


def read_kinect2_csv(path):
    """Kinect v2 body CSV: timestamp (100 ns ticks), then 25 x (x, y, z, state)."""
    times, frames, states = [], [], []
    with open(path, encoding="utf-8") as f:
        for line in f:
            fields = [v for v in line.strip().split(",") if v != ""]
            if len(fields) < 1 + 4 * 25:
                continue
            times.append(int(fields[0]) * 1e-7)
            vals = np.array([float(v) for v in fields[1:1 + 100]]).reshape(25, 4)
            frames.append(vals[:, :3])
            states.append(vals[:, 3])
    pos = np.array(frames)
    tracked = np.array(states) >= 2
    joints = {name: pos[:, i] for i, name in enumerate(KINECT2_JOINTS)}
    ok = {name: tracked[:, i] for i, name in enumerate(KINECT2_JOINTS)}
    return np.array(times), joints, ok


def _axis_matrix(axis, deg):
    a = math.radians(deg)
    c, s = math.cos(a), math.sin(a)
    if axis == "X":
        return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    if axis == "Y":
        return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def read_bvh(path):
    """Parses a BVH file; returns frame time and joint positions per frame.

    Rotations compose in channel order (intrinsic, R = R1 R2 R3), the usual
    BVH convention; End Sites are named '<joint>.end'.
    """
    with open(path, encoding="utf-8") as f:
        tokens = f.read().split()
    i = 0
    joints = []  # (name, parent index, offset, channel names)
    stack = []
    pending = None
    while tokens[i] != "MOTION":
        t = tokens[i]
        if t in ("ROOT", "JOINT"):
            pending = tokens[i + 1]
            i += 2
        elif t == "End":
            pending = joints[stack[-1]][0] + ".end"
            i += 2
        elif t == "{":
            joints.append([pending, stack[-1] if stack else -1, None, []])
            stack.append(len(joints) - 1)
            i += 1
        elif t == "}":
            stack.pop()
            i += 1
        elif t == "OFFSET":
            joints[stack[-1]][2] = np.array([float(v) for v in tokens[i + 1:i + 4]])
            i += 4
        elif t == "CHANNELS":
            n = int(tokens[i + 1])
            joints[stack[-1]][3] = tokens[i + 2:i + 2 + n]
            i += 2 + n
        else:
            i += 1
    n_frames = int(tokens[i + 2])
    frame_time = float(tokens[i + 5])
    data = np.array([float(v) for v in tokens[i + 6:]]).reshape(n_frames, -1)
    pos = {j[0]: np.zeros((n_frames, 3)) for j in joints}
    for k in range(n_frames):
        col = 0
        rots = []
        for name, parent, offset, channels in joints:
            local_t = offset.copy()
            rot = np.eye(3)
            for ch in channels:
                v = data[k, col]
                col += 1
                if ch.endswith("position"):
                    local_t["XYZ".index(ch[0])] += v
                else:
                    rot = rot @ _axis_matrix(ch[0], v)
            if parent < 0:
                world_r, world_p = rot, local_t
            else:
                pr = rots[parent]
                world_p = pos[joints[parent][0]][k] + pr @ local_t
                world_r = pr @ rot
            rots.append(world_r)
            pos[name][k] = world_p
    times = np.arange(n_frames) * frame_time
    ok = {name: np.ones(n_frames, dtype=bool) for name in pos}
    return times, pos, ok


def _point(joints, ok, spec):
    if spec.startswith("mid("):
        a, b = spec[4:-1].split(",")
        return 0.5 * (joints[a] + joints[b]), ok[a] & ok[b]
    return joints[spec], ok[spec]


def segment_stats(joints, ok, segments, scale):
    out = {}
    for seg, (a, b) in segments.items():
        pa, oka = _point(joints, ok, a)
        pb, okb = _point(joints, ok, b)
        mask = oka & okb
        d = np.linalg.norm(pb - pa, axis=1)[mask] * scale
        if d.size == 0:
            continue
        med = float(np.median(d))
        out[seg] = {
            "from": a,
            "to": b,
            "median_m": round(med, 5),
            "p05_m": round(float(np.percentile(d, 5)), 5),
            "p95_m": round(float(np.percentile(d, 95)), 5),
            "mad_m": round(float(np.median(np.abs(d - med))), 5),
            "frames": int(d.size),
        }
    return out


def main():
    result = {
        "units": "metres",
        "statistic": "median over frames; p05/p95 percentiles; mad = median absolute deviation",
        "frames_used": "Kinect: frames where both joints are tracked (state 2); BVH: all frames",
        "recordings": {},
    }
    for name in sorted(os.listdir(HERE)):
        path = os.path.join(HERE, name)
        if name.endswith(".csv") and name.startswith("kinect2-"):
            times, joints, ok = read_kinect2_csv(path)
            layout, scale = "kinect2", 1.0
        elif name.endswith(".bvh") and name.startswith("cmu-"):
            times, joints, ok = read_bvh(path)
            layout, scale = "cmu_bvh", CMU_UNIT_M
        else:
            continue
        dt = np.diff(times)
        result["recordings"][name] = {
            "layout": layout,
            "unit_scale_to_m": scale,
            "frames": int(len(times)),
            "duration_s": round(float(times[-1] - times[0]), 4),
            "median_frame_interval_s": round(float(np.median(dt)), 6),
            "segments": segment_stats(joints, ok, SEGMENTS[layout], scale),
        }
    out = os.path.join(HERE, "segment_lengths.json")
    with open(out, "w", encoding="utf-8") as f:
        json.dump(result, f, indent=2, sort_keys=False)
        f.write("\n")
    print(f"wrote {out}", file=sys.stderr)


if __name__ == "__main__":
    main()
