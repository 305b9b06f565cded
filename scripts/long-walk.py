#!/usr/bin/env python3
"""A long walk through `navaid run` with its resources watched (docs/robustness.md, "Long walks").

Simulates lab-walk-1 (a closed 26.2 m loop) for LAPS laps, runs `navaid run` on it and samples the
process every second from /proc: resident memory, open file descriptors, threads. Writes
OUT/resources.csv, OUT/frame-time.csv (median per-frame time per block of the walk),
OUT/long-walk.png and OUT/verdict.json, and exits 1 unless
  - resident memory after warm-up (the first WARMUP share of the walk) grows < 10 % during the walk
    (--max-rss-growth); the evaluation at the end (ATE, NEES over the whole run at once, after the
    line "evaluating the run") is reported as its own peak, not judged,
  - the per-frame time does not grow (median of the last block <= 1.25 x the first after warm-up),
  - file descriptors and threads do not grow: the fewest seen in the last tenth of the run are no
    more than the fewest seen in the first tenth after warm-up (a worker thread or a file that
    comes and goes is not a leak; one that stays raises the floor).
Usage: long-walk.py --navaid BUILD/apps/navaid --out DIR [--laps N] [--mode features|images]
                    [--device NAME] [--max-rss-growth X] [--set KEY=VALUE ...]
With --device (images only: a device maps from depth images) every layer runs: estimator, mapping,
guidance, cues and speech.
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import time


def proc_sample(pid):
    rss_kb = threads = None
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                rss_kb = int(line.split()[1])
            elif line.startswith("Threads:"):
                threads = int(line.split()[1])
    fds = len(os.listdir(f"/proc/{pid}/fd"))
    return rss_kb, fds, threads


def evaluation_started(log_path):
    """Whether navaid run has said the walk is over (its log's last few kB)."""
    try:
        with open(log_path, "rb") as f:
            f.seek(max(0, os.path.getsize(log_path) - 4096))
            return b"evaluating the run" in f.read()
    except OSError:
        return False


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--navaid", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--laps", type=int, default=150)
    ap.add_argument("--mode", choices=["features", "images"], default="features")
    ap.add_argument("--warmup", type=float, default=0.2, help="share of the run that is warm-up")
    ap.add_argument("--blocks", type=int, default=10, help="blocks of the walk for the frame-time curve")
    ap.add_argument("--no-time-check", action="store_true",
                    help="report the per-frame time without judging it (tests: a loaded machine is not a regression)")
    ap.add_argument("--max-rss-growth", type=float, default=0.10,
                    help="allowed growth of resident memory after warm-up (share)")
    ap.add_argument("--set", action="append", default=[], help="extra simulate --set (images: resolution)")
    ap.add_argument("--device", help="navaid run --device NAME: the full device (needs --mode images)")
    ap.add_argument("--recording", help="walk this recording (made by an earlier long-walk.py) instead of simulating")
    a = ap.parse_args()
    if a.device and a.mode != "images":
        ap.error("--device needs --mode images (a device maps from depth images)")
    os.makedirs(a.out, exist_ok=True)
    rec, run = os.path.join(a.out, "recording"), os.path.join(a.out, "run")

    sim = [a.navaid, "simulate", "--scenario", "lab-walk-1", "--mount", "hand", "--seed", "1", "--overwrite",
           "--out", rec, "--set", f"simulation.mode={a.mode}", "--set", f"simulation.laps={a.laps}"]
    for s in a.set:
        sim += ["--set", s]
    if a.recording:
        rec = a.recording
    else:
        subprocess.run(sim, check=True, stdout=subprocess.DEVNULL)

    # The program is started without a shell; its output goes to a log.
    with open(os.path.join(a.out, "run.log"), "w") as log:
        start = time.monotonic()
        # -v: info lines, among them the one that says the walk is over.
        cmd = [a.navaid, "-v", "run", "--recording", rec, "--out", run, "--no-plot"]
        if a.device:
            cmd += ["--device", a.device]
        p = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT)
        samples = []  # (wall_s, rss_kb, fds, threads, evaluating)
        evaluating = False
        while p.poll() is None:
            try:
                sample = (time.monotonic() - start,) + proc_sample(p.pid)
            except (FileNotFoundError, ProcessLookupError, PermissionError):
                break
            evaluating = evaluating or evaluation_started(os.path.join(a.out, "run.log"))
            samples.append(sample + (int(evaluating),))
            time.sleep(1.0)
        p.wait()
    if p.returncode != 0:
        print(f"long-walk: navaid run failed ({p.returncode}); see {a.out}/run.log", file=sys.stderr)
        return 1
    samples = [s for s in samples if None not in s]
    with open(os.path.join(a.out, "resources.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["wall_s", "rss_kb", "fds", "threads", "evaluating"])
        w.writerows(samples)

    # Per-frame time, median per block of frames.
    with open(os.path.join(run, "timing.csv")) as f:
        ms = [float(r["ms"]) for r in csv.DictReader(f)]
    n = len(ms) // a.blocks
    blocks = [statistics.median(ms[i * n:(i + 1) * n]) for i in range(a.blocks)]
    with open(os.path.join(a.out, "frame-time.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["block", "first_frame", "median_ms"])
        w.writerows((i, i * n, b) for i, b in enumerate(blocks))

    walk = [s for s in samples if not s[4]]
    evaluation = [s for s in samples if s[4]]
    if not walk:
        print("long-walk: no sample of the walk itself", file=sys.stderr)
        return 1
    warm = [s for s in walk if s[0] >= a.warmup * walk[-1][0]]
    if len(warm) < 3:
        print("long-walk: the run was too short to watch (fewer than 3 samples after warm-up)", file=sys.stderr)
        return 1
    rss0, rss_max = warm[0][1], max(s[1] for s in warm)
    tenth = max(1, len(warm) // 10)
    first, last = warm[:tenth], warm[-tenth:]
    first_block = int(a.warmup * a.blocks)
    verdict = {
        "laps": a.laps, "mode": a.mode, "device": a.device, "frames": len(ms), "wall_s": samples[-1][0],
        "rss_after_warmup_mb": rss0 / 1024, "rss_max_mb": rss_max / 1024,
        "rss_growth": rss_max / rss0 - 1,
        "rss_evaluation_peak_mb": max((s[1] for s in evaluation), default=0) / 1024,
        "frame_ms_first_block": blocks[first_block], "frame_ms_last_block": blocks[-1],
        "fds_after_warmup": min(s[2] for s in first), "fds_end": min(s[2] for s in last),
        "threads_after_warmup": min(s[3] for s in first), "threads_end": min(s[3] for s in last),
    }
    checks = {
        f"memory grows < {a.max_rss_growth:.0%}": verdict["rss_growth"] < a.max_rss_growth,
        "no file handle leak": verdict["fds_end"] <= verdict["fds_after_warmup"],
        "no thread leak": verdict["threads_end"] <= verdict["threads_after_warmup"],
    }
    if not a.no_time_check:
        checks["frame time does not grow"] = blocks[-1] <= 1.25 * blocks[first_block]
    verdict["checks"] = checks
    with open(os.path.join(a.out, "verdict.json"), "w") as f:
        json.dump(verdict, f, indent=1)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, (m, t) = plt.subplots(2, 1, figsize=(7, 5))
        m.plot([s[0] for s in samples], [s[1] / 1024 for s in samples])
        m.axvline(warm[0][0], ls="--", c="grey")
        if evaluation:
            m.axvline(evaluation[0][0], ls=":", c="red")  # the walk is over: the run's evaluation
        m.set_ylabel("resident memory [MB]")
        m.set_xlabel("wall time [s]")
        t.plot([i * n for i in range(a.blocks)], blocks, marker="o")
        t.set_ylabel("median per-frame time [ms]")
        t.set_xlabel("frame")
        fig.tight_layout()
        fig.savefig(os.path.join(a.out, "long-walk.png"), dpi=100)
    except ImportError:
        pass
    print(json.dumps(verdict, indent=1))
    return 0 if all(checks.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
