#!/usr/bin/python3
"""Monte-Carlo consistency figure: the per-epoch average NEES (ANEES_k) of position and of
orientation over time, with the two-sided chi-square bounds of ANEES_k and the time average with
its conservative bounds.

Input: consistency.csv (columns epoch,t,anees_pos,anees_rot,runs; t in seconds) and
consistency.json, both written by `navaid consistency --out DIR`. Usable on its own.
"""
import argparse
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from figure_csv import read_numeric_csv  # noqa: E402

COLUMNS = ["epoch", "t", "anees_pos", "anees_rot", "runs"]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("csv", help="per-epoch ANEES (consistency.csv)")
    parser.add_argument("json", help="statistics and bounds (consistency.json)")
    parser.add_argument("--out", required=True, help="output image (.png, .pdf, .svg)")
    args = parser.parse_args()

    data = read_numeric_csv(args.csv, COLUMNS, "plot_consistency")
    if data is None:
        return 2
    with open(args.json) as f:
        stats = json.load(f)
    t = data[:, 1] - data[:, 1][0]
    runs = int(data[0, 4])
    pct = round(100 * stats["confidence"])

    fig, axes = plt.subplots(2, 1, figsize=(10, 7), sharex=True)
    for ax, column, key, label in [(axes[0], 2, "position", "position"), (axes[1], 3, "orientation", "orientation")]:
        s = stats[key]
        b = s["epoch_bounds"]
        anees = data[:, column]
        ax.plot(t, anees, lw=0.8, color="tab:blue", label=f"ANEES$_k$ over {runs} runs")
        ax.axhline(b["lower"], color="tab:red", ls="--", lw=1,
                   label=f"{pct} % bounds of ANEES$_k$ [{b['lower']:.2f}, {b['upper']:.2f}]")
        ax.axhline(b["upper"], color="tab:red", ls="--", lw=1)
        ax.axhline(s["dof"], color="gray", ls=":", lw=1, label=f"expected ({s['dof']})")
        ax.axhline(s["time_average"], color="black", lw=1.2,
                   label=f"time average {s['time_average']:.2f} "
                         f"({'consistent' if s['consistent'] else 'inconsistent'})")
        # Linear: the bounds matter; a start-up transient or a far outlier must not squash them.
        top = max(1.5 * b["upper"], 1.1 * float(np.percentile(anees, 99)))
        ax.set_ylim(0.0, top)
        ax.set_ylabel(f"{label} ANEES")
        ax.set_title(f"{label}: {100 * s['fraction_of_epochs_inside']:.1f} % of {len(t)} epochs inside "
                     f"({s['epochs_below']} below, {s['epochs_above']} above)", fontsize=10)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, loc="lower right", framealpha=0.85)
    axes[1].set_xlabel("time since the first shared epoch [s]")
    fig.suptitle(f"Monte-Carlo NEES consistency ({runs} runs, {pct} % two-sided chi-square bounds)")
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main())
