#!/usr/bin/env bash
# The randomized safety study of the closed-loop simulated users (docs/simulated-users.md, "The
# safety study"): one command, three parts, every trial seeded and replayable.
#   corridor         smart-cane      random layouts   400 trials
#   obstacle-course  augmented-cane  random layouts   400 trials
#   route2           none (cane)     moving people    200 trials (their paths move by the seed)
# Usage: bash scripts/safety-study.sh OUT_DIR [JOBS] [SCALE]
#   JOBS: trials at once (2); SCALE: a fraction of the trial counts (1; 0.01 for a smoke run).
# Writes OUT_DIR/<part>/ (trials.csv, summary.json, summary.md: each guidance into an obstacle with
# its replay command) and OUT_DIR/summary.md (all parts, the wall time).
set -euo pipefail
out=${1:?usage: safety-study.sh OUT_DIR [JOBS] [SCALE]}
jobs=${2:-2}
scale=${3:-1}
here="$(cd "$(dirname "$0")/.." && pwd)"
navaid=${NAVAID:-"$here/build/apps/navaid"}
[[ -x "$navaid" ]] || { echo "safety-study: no navaid at $navaid (build first, or set NAVAID)" >&2; exit 2; }
mkdir -p "$out"
count() { python3 -c "import math,sys; print(max(1, math.ceil($1 * float(sys.argv[1]))))" "$scale"; }
start=$(date +%s)
run_part() {  # name scenario device layouts trials
  local n
  n=$(count "$5")
  echo "safety-study: $1: $n trials ($2, $3, $4 layouts)" >&2
  "$navaid" trial --scenario "$2" --device "$3" --layouts "$4" --seeds "1..$n" --jobs "$jobs" --keep failures \
    --quiet --out "$out/$1" > /dev/null
}
run_part corridor-smart-cane corridor smart-cane random 400
run_part obstacle-course-augmented-cane obstacle-course augmented-cane random 400
run_part route2-cane route2 none random 200
wall=$(( $(date +%s) - start ))
python3 - "$out" "$wall" "$jobs" <<'PY'
import json, sys, pathlib
out, wall, jobs = pathlib.Path(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
parts = ["corridor-smart-cane", "obstacle-course-augmented-cane", "route2-cane"]
rows, total, into = [], 0, []
for p in parts:
    j = json.loads((out / p / "summary.json").read_text())
    total += j["trials"]
    s = j["success"]
    m = lambda k: "-" if j[k] is None else f'{j[k]["mean"]:.2f}'
    rows.append(f'| {p} | {j["trials"]} | {100*s["rate"]:.1f} % [{100*s["ci95"][0]:.1f}, {100*s["ci95"][1]:.1f}] | '
                f'{m("body_contacts_per_trial")} | {m("head_contacts_per_trial")} | {m("cane_contacts_per_trial")} | '
                f'{m("guidance_into_obstacle_per_trial")} | {j["time"]["per_trial_wall_s"]["mean"]:.2f} |')
    into += [(p, g) for g in j["guidance_into_obstacle"]]
text = ["# Safety study (simulated users, not human results)", "",
        f"{total} trials in {wall} s ({wall/60:.1f} min) with {jobs} jobs.", "",
        "| part | trials | success [95 % CI] | body contacts / trial | head | cane contacts / trial | guidance into an obstacle / trial | wall s / trial |",
        "|---|---|---|---|---|---|---|---|"] + rows
text += ["", f"## Guidance into an obstacle: {len(into)} episodes", "",
         "| part | seed | t [s] | instruction | obstacle | replay |", "|---|---|---|---|---|---|"]
text += [f'| {p} | {g["seed"]} | {g["t_s"]:.1f} | {g["instruction"]} | {g["obstacle"]} | `{g["replay"]}` |' for p, g in into]
(out / "summary.md").write_text("\n".join(text) + "\n")
print("\n".join(text[:6 + len(rows)]))
PY
