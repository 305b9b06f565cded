#!/usr/bin/python3
"""Top view of a `navaid run`: the estimated track coloured by estimator mode, over the ground truth.

Inputs are CSV files with a header row and columns t,x,y,z,mode (seconds, metres, the estimator
mode of each pose: rgbd-vio, vio, imu-only, lost). Written by `navaid run` into
<run>/topview.data/; usable on its own.
"""
import argparse
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

MODE_COLOURS = {
    "rgbd-vio": "tab:blue",
    "vio": "tab:green",
    "imu-only": "tab:orange",
    "lost": "tab:red",
}


def read_track(path):
    """Returns t, xyz (n x 3) and the mode names, or exits with a message."""
    with open(path, encoding="utf-8") as f:
        header = f.readline().strip().split(",")
        rows = [line.strip().split(",") for line in f if line.strip()]
    if header[:5] != ["t", "x", "y", "z", "mode"]:
        sys.exit(f"plot_run_topview: {path}: header must start with t,x,y,z,mode")
    if not rows:
        sys.exit(f"plot_run_topview: {path} has no rows")
    t = np.array([float(r[0]) for r in rows])
    xyz = np.array([[float(r[1]), float(r[2]), float(r[3])] for r in rows])
    return t, xyz, [r[4] for r in rows]


def draw_by_mode(ax, xyz, modes):
    """One line per run of equal modes; each run starts at the previous run's last point, so the
    track stays continuous and every segment has the colour of the mode it ends in."""
    seen = set()
    start = 0
    for i in range(1, len(modes) + 1):
        if i < len(modes) and modes[i] == modes[start]:
            continue
        lo = max(start - 1, 0)
        mode = modes[start]
        colour = MODE_COLOURS.get(mode, "tab:purple")
        ax.plot(xyz[lo:i, 0], xyz[lo:i, 1], "-", color=colour, lw=1.6,
                label=None if mode in seen else f"estimate: {mode}")
        seen.add(mode)
        start = i


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--estimate", required=True, help="estimated track, t,x,y,z,mode")
    parser.add_argument("--groundtruth", help="ground truth, same columns (mode ignored)")
    parser.add_argument("--enu", help="estimate in ENU through T_ENU_W (GPS), unaligned")
    parser.add_argument("--frame", default="", help="name of the plot frame, for the axis labels")
    parser.add_argument("--title", default="")
    parser.add_argument("--out", required=True, help="output image (.png, .pdf, .svg)")
    args = parser.parse_args()

    fig, ax = plt.subplots(figsize=(8, 7))
    if args.groundtruth:
        _, gt, _ = read_track(args.groundtruth)
        ax.plot(gt[:, 0], gt[:, 1], "-", color="0.55", lw=3.0, alpha=0.6, label="ground truth")
    if args.enu:
        _, enu, _ = read_track(args.enu)
        ax.plot(enu[:, 0], enu[:, 1], "--", color="tab:brown", lw=1.0, label="estimate in ENU (GPS, unaligned)")
    _, est, modes = read_track(args.estimate)
    draw_by_mode(ax, est, modes)
    ax.plot(est[0, 0], est[0, 1], "o", color="k", ms=5, label="start")
    ax.plot(est[-1, 0], est[-1, 1], "s", color="k", ms=5, label="end")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    title = "\n".join(x for x in (args.title, args.frame) if x)
    if title:
        ax.set_title(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
