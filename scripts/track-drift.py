#!/usr/bin/env python3
"""How far a front end's tracks drift as they age, against a recording's ground truth.

For every observation of a track (the feature-level recording `navaid run --save-features` writes),
the distance in pixels from the epipolar line of the track's first observation under the
ground-truth relative pose: what the tracked point has slid across that line since it was first
seen. Needs no depth; sees only the drift across the line (the whole drift is larger); pairs
closer than 5 cm apart are left out (the line is undefined without a baseline). Pinhole cameras
without distortion (navaid's simulated ones).

Usage: scripts/track-drift.py RECORDING TRACKS
  RECORDING  the recording the tracks came from (calibration.yaml, groundtruth.csv)
  TRACKS     the folder --save-features wrote (features.csv)
Prints, per track age, the count, median, p95 and the shares beyond 2 and 5 px.
"""
import csv
import sys

import numpy as np

AGES_S = [(0, 0.5), (0.5, 1), (1, 2), (2, 4), (4, float("inf"))]
MIN_BASELINE_M = 0.05


def quat_to_rot(w, x, y, z):
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def numbers_after(lines, key):
    line = next((l for l in lines if l.strip().startswith(key)), None)
    if line is None:
        sys.exit(f"track-drift: calibration.yaml has no {key}")
    return [float(v) for v in line.split("[", 1)[1].rstrip().rstrip("]").split(",")]


def read_camera(recording):
    lines = open(recording + "/calibration.yaml").read().splitlines()
    model = next((l.split(":", 1)[1].strip() for l in lines if l.strip().startswith("distortion_model:")), "none")
    if model != "none":
        sys.exit(f"track-drift: the first camera has distortion model '{model}'; only undistorted pinholes")
    fx, fy, cx, cy = numbers_after(lines, "intrinsics:")
    return (fx, fy, cx, cy), quat_to_rot(*numbers_after(lines, "q_wxyz:")), np.array(numbers_after(lines, "t_m:"))


def camera_poses(recording, R_BC, t_BC):
    gt = np.array([[float(v) for v in row[:8]] for row in list(csv.reader(open(recording + "/groundtruth.csv")))[1:]])
    if len(gt) < 2:
        sys.exit("track-drift: groundtruth.csv needs at least two samples")

    def pose(t):  # T_W_C at t: position interpolated, the nearer sample's rotation
        i = int(np.clip(np.searchsorted(gt[:, 0], t), 1, len(gt) - 1))
        a = (t - gt[i - 1, 0]) / (gt[i, 0] - gt[i - 1, 0])
        R_WB = quat_to_rot(*gt[i if a > 0.5 else i - 1, 4:8])
        return R_WB @ R_BC, R_WB @ t_BC + (1 - a) * gt[i - 1, 1:4] + a * gt[i, 1:4]
    return pose


def drifts(tracks, intrinsics, pose):
    fx, fy, cx, cy = intrinsics
    first = {}
    out = []  # (age s, px)
    for row in csv.DictReader(open(tracks + "/features.csv")):
        if not row["track_id"]:
            continue  # a frame without features
        t, tid = int(row["t_ns"]), int(row["track_id"])
        x = np.array([(float(row["u"]) - cx) / fx, (float(row["v"]) - cy) / fy, 1.0])
        R_WC, p_WC = pose(t)
        if tid not in first:
            first[tid] = (t, R_WC, p_WC, x)
            continue
        t0, R0, p0, x0 = first[tid]
        R, tr = R_WC.T @ R0, R_WC.T @ (p0 - p_WC)  # camera at t0 into the camera at t
        if np.linalg.norm(tr) < MIN_BASELINE_M:
            continue
        line = np.cross(tr, R @ x0)  # the epipolar line of x0 on the normalized plane
        out.append(((t - t0) * 1e-9, fx * abs(x @ line) / np.hypot(line[0], line[1])))
    return len(first), np.array(out).reshape(-1, 2)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    recording, tracks = sys.argv[1], sys.argv[2]
    intrinsics, R_BC, t_BC = read_camera(recording)
    n_tracks, e = drifts(tracks, intrinsics, camera_poses(recording, R_BC, t_BC))
    print(f"{tracks}: {n_tracks} tracks, {len(e)} observations with a baseline of {MIN_BASELINE_M * 100:.0f} cm or more")
    print("age [s]    observations  median px  p95 px  >2 px   >5 px")
    for lo, hi in AGES_S:
        s = e[(e[:, 0] >= lo) & (e[:, 0] < hi), 1]
        if len(s):
            print(f"{lo:4.1f}-{hi:<5.1f} {len(s):12d}  {np.median(s):9.2f}  {np.percentile(s, 95):6.2f}"
                  f"  {np.mean(s > 2) * 100:5.1f}%  {np.mean(s > 5) * 100:5.1f}%")


if __name__ == "__main__":
    main()
