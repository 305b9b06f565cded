#!/usr/bin/python3
"""Top view of several methods' trajectories and the ground truth on one recording (a paper's
trajectory figure, e.g. RGBD-VIO Fig. 5), and beside it each method's position error over time
(errors of a few centimetres are invisible in a top view of a 20 m walk).

Input: the CSV that `navaid reproduce` writes (trajectories.csv), columns method,t,x,y,z (seconds,
metres), the ground truth under the method name "ground truth", every estimate already aligned onto
it. Usable on its own.
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

COLUMNS = ["method", "t", "x", "y", "z"]
GROUND_TRUTH = "ground truth"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("csv", help="aligned trajectories (trajectories.csv)")
    parser.add_argument("--out", required=True, help="output image (.png, .pdf, .svg)")
    parser.add_argument("--title", default="")
    args = parser.parse_args()

    tracks = {}  # method -> ([t], [x], [y]) in file order
    with open(args.csv, newline="") as f:
        reader = csv.reader(f)
        if next(reader, None) != COLUMNS:
            print(f"plot_reproduction_trajectories: {args.csv}: expected columns {','.join(COLUMNS)}", file=sys.stderr)
            return 2
        for row in reader:
            if len(row) != len(COLUMNS):
                print(f"plot_reproduction_trajectories: {args.csv}: bad row {row}", file=sys.stderr)
                return 2
            ts, xs, ys = tracks.setdefault(row[0], ([], [], []))
            ts.append(float(row[1]))
            xs.append(float(row[2]))
            ys.append(float(row[3]))
    if GROUND_TRUTH not in tracks or len(tracks) < 2:
        print(f"plot_reproduction_trajectories: {args.csv} needs the ground truth and at least one method", file=sys.stderr)
        return 2

    fig, (ax, err) = plt.subplots(1, 2, figsize=(13, 5.8), gridspec_kw={"width_ratios": [1.15, 1]})
    gt, gx, gy = (np.asarray(v) for v in tracks.pop(GROUND_TRUTH))
    ax.plot(gx, gy, "-", color="0.2", lw=2.2, label=GROUND_TRUTH, zorder=1)
    ax.plot(gx[0], gy[0], "o", color="0.2", ms=6, zorder=3)
    styles = ["-", "--", "-.", ":"]
    for k, (method, (ts, xs, ys)) in enumerate(tracks.items()):
        ts, xs, ys = np.asarray(ts), np.asarray(xs), np.asarray(ys)
        line = ax.plot(xs, ys, styles[k % len(styles)], lw=1.2, label=method, zorder=2)[0]
        # Horizontal error against the ground truth interpolated at the estimate's times.
        e = np.hypot(xs - np.interp(ts, gt, gx), ys - np.interp(ts, gt, gy))
        err.plot(ts, e, styles[k % len(styles)], lw=1.0, color=line.get_color(),
                 label=f"{method} (RMSE {np.sqrt(np.mean(e ** 2)):.4f} m)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=9)
    ax.set_title("top view (o start)", fontsize=10)
    err.set_xlabel("time [s]")
    err.set_ylabel("horizontal position error [m]")
    err.set_ylim(bottom=0.0)
    err.grid(True, alpha=0.3)
    err.legend(loc="upper left", fontsize=9)
    if args.title:
        fig.suptitle(args.title, fontsize=11)
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main())
