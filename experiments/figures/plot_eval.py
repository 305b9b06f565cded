#!/usr/bin/python3
"""Trajectory evaluation figure: top view of ground truth and aligned estimate, and the position
error over time.

Input: the per-pose CSV that `navaid eval --out DIR` writes (DIR/eval.csv), with a header row and
columns t,gt_x,gt_y,gt_z,est_x,est_y,est_z,position_error_m,rotation_error_deg (seconds, metres,
degrees). Usable on its own.
"""
import argparse
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from figure_csv import read_numeric_csv  # noqa: E402

COLUMNS = ["t", "gt_x", "gt_y", "gt_z", "est_x", "est_y", "est_z", "position_error_m", "rotation_error_deg"]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("csv", help="per-pose errors (eval.csv)")
    parser.add_argument("--out", required=True, help="output image (.png, .pdf, .svg)")
    parser.add_argument("--title", default="")
    args = parser.parse_args()

    data = read_numeric_csv(args.csv, COLUMNS, "plot_eval")
    if data is None:
        return 2
    col = {name: data[:, i] for i, name in enumerate(COLUMNS)}
    t = col["t"] - col["t"][0]

    fig, (top, err) = plt.subplots(1, 2, figsize=(12, 5.5), gridspec_kw={"width_ratios": [1.2, 1]})
    top.plot(col["gt_x"], col["gt_y"], "-", color="0.25", lw=1.4, label="ground truth")
    top.plot(col["est_x"], col["est_y"], "-", color="tab:red", lw=1.0, label="estimate (aligned)")
    top.plot(col["gt_x"][0], col["gt_y"][0], "o", color="0.25", ms=5)
    top.set_aspect("equal", adjustable="datalim")
    top.set_xlabel("x [m]")
    top.set_ylabel("y [m]")
    top.set_title("top view (o start)")
    top.grid(True, alpha=0.3)
    top.legend(loc="best", fontsize=8)

    e = col["position_error_m"]
    rmse = float(np.sqrt(np.mean(e**2)))
    err.plot(t, e, "-", color="tab:red", lw=1.0, label="position error")
    err.axhline(rmse, color="tab:red", ls="--", lw=0.8, label=f"RMSE {rmse:.4f} m")
    err.set_xlabel("time since first matched pose [s]")
    err.set_ylabel("position error [m]")
    err.set_ylim(bottom=0.0)
    err.grid(True, alpha=0.3)
    rot = err.twinx()
    rot.plot(t, col["rotation_error_deg"], "-", color="tab:blue", lw=0.8, alpha=0.7, label="rotation error")
    rot.set_ylabel("rotation error [deg]", color="tab:blue")
    rot.set_ylim(bottom=0.0)
    lines = err.get_lines() + rot.get_lines()
    err.legend(lines, [ln.get_label() for ln in lines], loc="upper left", fontsize=8)

    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
