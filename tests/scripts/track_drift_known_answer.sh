#!/usr/bin/env bash
# Known answer of scripts/track-drift.py: simulated feature tracks carry white pixel noise of
# sigma = 1 px (simulation's features.pixel_sigma) and no drift, so the distance of an observation
# from its first observation's epipolar line is |N(0, sqrt(2) sigma)| across the line: median
# 0.674 * sqrt(2) = 0.95 px at every age. A wrong pose, frame or line shows as pixels of error.
# Usage: track_drift_known_answer.sh NAVAID WORK_DIR
set -euo pipefail
navaid=$1
work=$2
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
rm -rf "$work"
mkdir -p "$work"
"$navaid" simulate --scenario lab-walk-1 --mount hand --set simulation.mode=features --set duration=8 --seed 1 \
  --out "$work/walk" >/dev/null
/usr/bin/python3 "$source_dir/scripts/track-drift.py" "$work/walk" "$work/walk" | tee "$work/drift.txt"
# Rows: age range, observations, median, p95, >2 px, >5 px.
awk 'NR > 2 {
  rows++
  if ($2 < 1000) { print "too few observations in " $1; bad = 1 }
  if ($3 > 1.4) { print "median " $3 " px at ages " $1 ": drift where the simulation has none"; bad = 1 }
  if (rows == 1 && ($3 < 0.85 || $3 > 1.05)) { print "median " $3 " px at ages " $1 ", expected 0.95"; bad = 1 }
} END { if (rows < 4) { print "expected rows for 4 ages or more, found " rows; bad = 1 } exit bad }' "$work/drift.txt"
echo "track_drift_known_answer: passed"
