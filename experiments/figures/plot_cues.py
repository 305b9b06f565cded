#!/usr/bin/python3
"""Cue timeline of `navaid cues`: actuator states, cues by priority and speech against time.

Reads cues.csv (docs/interaction.md) and the actuator names; writes one figure with three rows:
each actuator's drive (bars while on, hatched while pulsing), every cue offered to the scheduler
by priority and outcome, and the spoken messages as intervals.
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

OUTCOME_STYLE = {
    "sent": ("o", "tab:blue"), "refreshed": (".", "tab:cyan"), "switched-off": ("x", "tab:gray"),
    "spoken": ("s", "tab:green"), "interrupted": ("X", "tab:red"), "preempted": ("v", "tab:red"),
    "rate-limited": ("|", "tab:orange"), "duplicate": ("_", "tab:orange"), "expired": ("d", "tab:purple"),
}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("cues", help="cues.csv")
    parser.add_argument("--actuators", required=True, help="comma-separated actuator names, index order")
    parser.add_argument("--device", default="")
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    names = args.actuators.split(",")
    with open(args.cues, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        print(f"plot_cues: {args.cues} has no events", file=sys.stderr)
    # A recording's own clock (seconds since 1970 in simulated and real recordings): time from the
    # first event instead, so the axis reads in seconds of the run.
    t_first = min(float(r["t_s"]) for r in rows) if rows else 0.0
    shifted = t_first > 1e6
    if shifted:
        for r in rows:
            r["t_s"] = str(float(r["t_s"]) - t_first)
    t_end = max([float(r["t_s"]) for r in rows] + [1.0]) + 1.0

    fig, (ax_act, ax_cue, ax_speech) = plt.subplots(3, 1, figsize=(12, 7), sharex=True,
                                                    gridspec_kw={"height_ratios": [2, 1.4, 0.8]})
    # Actuators: a pattern holds until the next pattern or its hold runs out.
    patterns = [r for r in rows if r["channel"] == "haptic" and r["pattern"]]
    for i, r in enumerate(patterns):
        t0 = float(r["t_s"])
        t_next = float(patterns[i + 1]["t_s"]) if i + 1 < len(patterns) else t_end
        if r["pattern"] == "off":
            continue
        for cmd in r["pattern"].split(";"):
            a, level, on, off, hold = (int(x) for x in cmd.split(":"))
            t1 = min(t_next, t0 + hold / 1000.0)
            alpha = 0.3 + 0.7 * min(abs(level), 1000) / 1000.0
            if on > 0 and off > 0:
                t = t0
                while t < t1:
                    ax_act.broken_barh([(t, min(on / 1000.0, t1 - t))], (a - 0.35, 0.7), color="tab:blue", alpha=alpha)
                    t += (on + off) / 1000.0
            else:
                ax_act.broken_barh([(t0, t1 - t0)], (a - 0.35, 0.7), color="tab:blue", alpha=alpha)
    ax_act.set_yticks(range(len(names)))
    ax_act.set_yticklabels(names)
    ax_act.set_ylim(-0.6, len(names) - 0.4)
    ax_act.set_title(f"{args.device} actuators" if args.device else "actuators")

    for outcome, (marker, color) in OUTCOME_STYLE.items():
        sel = [r for r in rows if r["outcome"] == outcome]
        if sel:
            ax_cue.scatter([float(r["t_s"]) for r in sel], [int(r["priority"]) for r in sel], marker=marker,
                           color=color, label=outcome, s=22)
    ax_cue.set_ylabel("priority")
    ax_cue.legend(loc="upper right", fontsize=7, ncol=5)

    starts = {}
    for r in rows:
        if r["channel"] != "speech":
            continue
        if r["outcome"] == "spoken":
            starts = {"t": float(r["t_s"]), "text": r["text"], "d": float(r["duration_s"] or 0)}
        elif r["outcome"] in ("finished", "interrupted") and starts:
            t0 = starts["t"]
            ax_speech.broken_barh([(t0, float(r["t_s"]) - t0)], (0.1, 0.8),
                                  color="tab:red" if r["outcome"] == "interrupted" else "tab:green", alpha=0.6)
            ax_speech.text(t0, 0.5, starts["text"][:28], fontsize=6, va="center")
            starts = {}
    ax_speech.set_yticks([])
    ax_speech.set_ylabel("speech")
    ax_speech.set_xlabel("t from the first cue [s]" if shifted else "t [s]")
    ax_speech.set_xlim(0, t_end)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
