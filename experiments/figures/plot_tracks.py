#!/usr/bin/python3
"""Top view and height-over-time of one or more tracks.

Each series is LABEL=FILE where FILE is a CSV with a header row and columns t,x,y,z
(seconds, metres). Written by `navaid plot`; usable on its own.
"""
import argparse
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("series", nargs="+", help="LABEL=FILE.csv (columns t,x,y,z)")
    parser.add_argument("--out", required=True, help="output image (.png, .pdf, .svg)")
    parser.add_argument("--title", default="")
    parser.add_argument("--xlabel", default="x [m]")
    parser.add_argument("--ylabel", default="y [m]")
    parser.add_argument("--zlabel", default="z [m]")
    args = parser.parse_args()

    fig, (top, side) = plt.subplots(1, 2, figsize=(12, 5.5), gridspec_kw={"width_ratios": [1.2, 1]})
    t0 = None
    for item in args.series:
        label, _, path = item.partition("=")
        if not path:
            print(f"plot_tracks: series '{item}' is not LABEL=FILE", file=sys.stderr)
            return 2
        data = np.atleast_2d(np.loadtxt(path, delimiter=",", skiprows=1))
        if data.size == 0:
            print(f"plot_tracks: {path} has no rows", file=sys.stderr)
            return 2
        t, x, y, z = data[:, 0], data[:, 1], data[:, 2], data[:, 3]
        t0 = t[0] if t0 is None else min(t0, t[0])
        line, = top.plot(x, y, "-", lw=1.2, label=label)
        top.plot(x[0], y[0], "o", color=line.get_color(), ms=5)
        top.plot(x[-1], y[-1], "s", color=line.get_color(), ms=5)
        side.plot(t, z, "-", lw=1.0, color=line.get_color(), label=label)
    side_lines = side.get_lines()
    for ln in side_lines:
        ln.set_xdata(np.asarray(ln.get_xdata()) - t0)
    side.relim()
    side.autoscale_view()
    top.set_aspect("equal", adjustable="datalim")
    top.set_xlabel(args.xlabel)
    top.set_ylabel(args.ylabel)
    top.set_title("top view (o start, \u25a0 end)")
    top.grid(True, alpha=0.3)
    top.legend(loc="best", fontsize=8)
    side.set_xlabel("time since start [s]")
    side.set_ylabel(args.zlabel)
    side.grid(True, alpha=0.3)
    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
