#!/usr/bin/env python3
"""The map frame of a `plslam run` on a `plslam synth` folder against the scene's truth.

usage: tools/map_frame_truth.py RUN_OUT SYNTH_DIR

The synthetic world has z up and the floor at z = 0, so the true map frame's up is the
scene's z and the first camera's true height is its ground-truth z. The SLAM world is placed
in the scene through the first tracked frame (T_scene_world = T_scene_c0 * T_world_c0^-1).
Prints the first camera's height above the floor (map_frame.yaml against truth) and the angle
between the estimated and the true up. Standard library only.
"""
import math
import sys


def qmat(x, y, z, w):
    n = math.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def first_pose(path):
    for line in open(path):
        if line.strip() and not line.startswith("#"):
            v = [float(a) for a in line.split()]
            return v[0], v[1:4], qmat(*v[4:8])
    raise SystemExit(path + ": no pose")


def pose_at(path, t):
    for line in open(path):
        if line.strip() and not line.startswith("#"):
            v = [float(a) for a in line.split()]
            if abs(v[0] - t) < 1e-4:
                return v[1:4], qmat(*v[4:8])
    raise SystemExit(path + ": no pose at %.6f" % t)


def map_frame(path):
    kv = {}
    for line in open(path):
        line = line.split("#")[0]
        if ":" in line:
            k, v = line.split(":", 1)
            kv[k.strip()] = v.strip()
    nums = lambda k: [float(a) for a in kv[k].strip("[]").split(",")]
    return nums("translation"), qmat(*nums("rotation")), kv


def main():
    out, synth = sys.argv[1], sys.argv[2]
    t0, t_w_c0, R_w_c0 = first_pose(out + "/trajectory.txt")
    t_s_c0, R_s_c0 = pose_at(synth + "/groundtruth.txt", t0)
    t_m_w, R_m_w, kv = map_frame(out + "/map_frame.yaml")
    # Up in the SLAM world: estimated = row 2 of R_map_world; true = R_world_scene * z
    # = R_w_c0 * R_s_c0^T * z = R_w_c0 * (row 2 of R_s_c0).
    up_c0 = R_s_c0[2]
    up_true = [sum(R_w_c0[i][j] * up_c0[j] for j in range(3)) for i in range(3)]
    up_est = R_m_w[2]
    dot = max(-1.0, min(1.0, sum(a * b for a, b in zip(up_true, up_est))))
    # The first camera's centre in the map: T_map_world * t_w_c0; its true height: its scene z.
    c0_map_z = sum(R_m_w[2][j] * t_w_c0[j] for j in range(3)) + t_m_w[2]
    print("floor %s (%s points): first camera %.4f m above the floor, true %.4f m (error %+.4f m); "
          "up error %.3f deg" % (kv.get("floor_method"), kv.get("floor_source"), c0_map_z, t_s_c0[2],
                                 c0_map_z - t_s_c0[2], math.degrees(math.acos(dot))))


if __name__ == "__main__":
    main()
