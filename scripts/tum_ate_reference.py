#!/usr/bin/env python3
"""Independent reference of the TUM RGB-D benchmark's ATE, to cross-check pf2_eval.

Usage: tum_ate_reference.py GROUNDTRUTH ESTIMATE [--max-diff S]
Prints one JSON object: ate_rmse, ate_mean, ate_median, ate_std, ate_min, ate_max, pairs.

Written from the benchmark's definition (Sturm et al., IROS 2012, sec. VI-A): stamps are associated
greedily, closest pairs first, each stamp used once, within max-diff seconds; the estimate's
positions are aligned to the ground truth's by Horn's closed-form absolute orientation (here via the
SVD of the cross-covariance, which gives the same minimiser); the error of each pair is the
Euclidean distance after alignment. numpy only, so it shares no code with the C++ evaluator.
"""
import argparse
import json
import sys

import numpy


def read_trajectory(path):
    stamps, positions = [], []
    with open(path) as f:
        for line in f:
            fields = line.replace(",", " ").split()
            if not fields or fields[0].startswith("#"):
                continue
            values = [float(v) for v in fields[:8]]
            stamps.append(values[0])
            positions.append(values[1:4])
    return numpy.array(stamps), numpy.array(positions)


def associate(first, second, max_difference):
    candidates = sorted((abs(a - b), i, j)
                        for i, a in enumerate(first)
                        for j, b in enumerate(second)
                        if abs(a - b) < max_difference)
    used_first, used_second, matches = set(), set(), []
    for _, i, j in candidates:
        if i in used_first or j in used_second:
            continue
        used_first.add(i)
        used_second.add(j)
        matches.append((i, j))
    return sorted(matches)


def align(model, data):
    """Rotation R and translation t minimising sum |R model + t - data|^2 (3xN arrays)."""
    model_mean = model.mean(axis=1, keepdims=True)
    data_mean = data.mean(axis=1, keepdims=True)
    cross = (data - data_mean) @ (model - model_mean).T
    u, _, vt = numpy.linalg.svd(cross)
    correction = numpy.eye(3)
    if numpy.linalg.det(u) * numpy.linalg.det(vt) < 0:
        correction[2, 2] = -1
    rotation = u @ correction @ vt
    return rotation, data_mean - rotation @ model_mean


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("groundtruth")
    parser.add_argument("estimate")
    parser.add_argument("--max-diff", type=float, default=0.02)
    args = parser.parse_args()
    gt_stamps, gt_positions = read_trajectory(args.groundtruth)
    est_stamps, est_positions = read_trajectory(args.estimate)
    matches = associate(gt_stamps, est_stamps, args.max_diff)
    if len(matches) < 3:
        sys.exit("too few associated poses")
    data = numpy.array([gt_positions[i] for i, _ in matches]).T
    model = numpy.array([est_positions[j] for _, j in matches]).T
    rotation, translation = align(model, data)
    errors = numpy.sqrt(((rotation @ model + translation - data) ** 2).sum(axis=0))
    print(json.dumps({
        "ate_rmse": float(numpy.sqrt(numpy.mean(errors ** 2))),
        "ate_mean": float(numpy.mean(errors)),
        "ate_median": float(numpy.median(errors)),
        "ate_std": float(numpy.std(errors)),
        "ate_min": float(numpy.min(errors)),
        "ate_max": float(numpy.max(errors)),
        "pairs": len(matches),
    }))


if __name__ == "__main__":
    main()
