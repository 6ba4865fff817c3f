#!/usr/bin/env python3
"""Writes a ground-truth trajectory and a noisy, misaligned estimate of it (TUM format).

Usage: make_example_trajectories.py OUT_DIR [--poses N] [--noise METRES] [--seed S]

The ground truth is a hand-held-like wobbly loop at 30 Hz; the estimate is the same path moved by a
fixed rigid transform, its stamps shifted by 3 ms (within the 0.02 s association window), with
isotropic Gaussian noise per axis. The expected ATE RMSE is about sqrt(3) * noise.
"""
import argparse
import math
import os
import random


def quaternion_about_axis(axis, angle):
    norm = math.sqrt(sum(a * a for a in axis))
    s = math.sin(angle / 2.0) / norm
    return (axis[0] * s, axis[1] * s, axis[2] * s, math.cos(angle / 2.0))  # x y z w


def quaternion_multiply(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def rotate(q, v):
    qv = quaternion_multiply(quaternion_multiply(q, (v[0], v[1], v[2], 0.0)),
                             (-q[0], -q[1], -q[2], q[3]))
    return qv[:3]


def write_atomically(path, lines):
    temporary = path + ".tmp"
    with open(temporary, "w") as out:
        out.write("# timestamp tx ty tz qx qy qz qw\n")
        out.writelines(lines)
    os.replace(temporary, path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir")
    parser.add_argument("--poses", type=int, default=900)
    parser.add_argument("--noise", type=float, default=0.01)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)
    rng = random.Random(args.seed)

    misalignment_q = quaternion_about_axis((0.3, -0.8, 0.5), 1.2)
    misalignment_t = (0.8, -0.3, 1.1)
    gt_lines, est_lines = [], []
    for i in range(args.poses):
        s = i / 30.0
        t = (1.5 * math.cos(0.2 * s), 0.15 * math.sin(1.3 * s), 1.0 * math.sin(0.2 * s))
        q = quaternion_multiply(quaternion_about_axis((0, 1, 0), 0.2 * s),
                                quaternion_about_axis((1, 0, 0), 0.1 * math.sin(s)))
        gt_lines.append("%.6f %.6f %.6f %.6f %.6f %.6f %.6f %.6f\n" % ((1000.0 + s,) + t + q))
        moved = rotate(misalignment_q, t)
        noisy = [moved[k] + misalignment_t[k] + rng.gauss(0.0, args.noise) for k in range(3)]
        q_est = quaternion_multiply(misalignment_q, q)
        est_lines.append("%.6f %.6f %.6f %.6f %.6f %.6f %.6f %.6f\n"
                         % ((1000.003 + s,) + tuple(noisy) + q_est))
    write_atomically(os.path.join(args.out_dir, "groundtruth.txt"), gt_lines)
    write_atomically(os.path.join(args.out_dir, "estimate.txt"), est_lines)
    print("wrote %d poses to %s (expected ATE RMSE about %.4f m)"
          % (args.poses, args.out_dir, math.sqrt(3.0) * args.noise))


if __name__ == "__main__":
    main()
