#!/usr/bin/env bash
# navaid's main job. Until the simulator lands it summarises and plots real recorded data from
# ../shared/data: a GNSS receiver capture (converted to a navaid recording, then drawn as an ENU
# track) and the EuRoC V1_02 ground truth with a real estimator's trajectory.
# Usage: bash scripts/main-job.sh [OUT_DIR]   (default out/main-job)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 --target navaid

DATA=${NAVAID_DATA:-../shared/data}
OUT=${1:-out/main-job}
NAVAID=build/apps/navaid
if [ ! -d "$DATA/gpsd-nmea" ] || [ ! -d "$DATA/rpg-euroc-V1_02" ]; then
  echo "main-job: the real data sets are expected in $DATA (set NAVAID_DATA to their folder)" >&2
  exit 1
fi
rm -rf "$OUT"
mkdir -p "$OUT"

echo "== GNSS capture: summary, conversion to a navaid recording, ENU track"
$NAVAID info "$DATA/gpsd-nmea/haicom-305N.log" | tee "$OUT/gnss-capture-info.txt"
$NAVAID convert "$DATA/gpsd-nmea/haicom-305N.log" "$OUT/gnss-recording"
$NAVAID info --json "$OUT/gnss-recording" > "$OUT/gnss-recording-info.json"
$NAVAID plot "$OUT/gnss-recording" --out "$OUT/gnss-track.png"

echo "== EuRoC V1_02: ground truth and estimator trajectories"
$NAVAID info "$DATA/rpg-euroc-V1_02/vislam_ba" | tee "$OUT/euroc-info.txt"
$NAVAID plot "$DATA/rpg-euroc-V1_02/vislam_ba/stamped_groundtruth.txt" --out "$OUT/euroc-groundtruth.png"

echo "main-job: results in $OUT"
ls -1 "$OUT"
