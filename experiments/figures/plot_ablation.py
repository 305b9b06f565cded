#!/usr/bin/env python3
"""Grouped bar chart of an ablation study: one group per recording, one bar per variant, the
mean of a metric over seeds with its sample standard deviation. Reads navaid ablate's results.csv.

Usage: plot_ablation.py RESULTS_CSV METRIC OUT_PNG
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(argv):
    if len(argv) != 4:
        sys.exit(__doc__)
    path, metric, out = argv[1], argv[2], argv[3]
    values = {}  # (recording, variant) -> [metric values]
    recordings, variants = [], []
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if metric not in row:
                sys.exit(f"plot_ablation.py: {path} has no column {metric}")
            r, v = row["recording"], row["variant"]
            if r not in recordings:
                recordings.append(r)
            if v not in variants:
                variants.append(v)
            if row["status"] != "failed" and row[metric] != "":
                values.setdefault((r, v), []).append(float(row[metric]))
    width = 0.8 / max(1, len(variants))
    fig, ax = plt.subplots(figsize=(max(6, 1.2 * len(recordings) * len(variants) * 0.6 + 2), 4))
    for k, v in enumerate(variants):
        means, stds, xs = [], [], []
        for i, r in enumerate(recordings):
            vals = values.get((r, v), [])
            if not vals:
                continue
            m = sum(vals) / len(vals)
            s = math.sqrt(sum((x - m) ** 2 for x in vals) / (len(vals) - 1)) if len(vals) > 1 else 0.0
            xs.append(i + (k - (len(variants) - 1) / 2) * width)
            means.append(m)
            stds.append(s)
        ax.bar(xs, means, width, yerr=stds, capsize=3, label=v)
    ax.set_xticks(range(len(recordings)))
    ax.set_xticklabels(recordings, rotation=20, ha="right")
    ax.set_ylabel(metric)
    ax.set_title("ablation: mean ± std over seeds")
    ax.grid(axis="y", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=120)


if __name__ == "__main__":
    main(sys.argv)
