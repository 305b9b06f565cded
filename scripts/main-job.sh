#!/usr/bin/env bash
# navaid's main job: full-device runs on rendered recordings (the Smart Cane down its corridor,
# W-ROMA's hand guidance in the lab: every layer from RGB-D + IMU to the steering wheel, the hand
# unit and speech, with report.html), a full-device simulated walk (eLabrador Route 1 with the head mount: RGB-D
# images, labels, IMU, GNSS, magnetometer, ground truth), the whole route again in feature mode
# run through the sliding-window estimator and evaluated against ground truth, the semantic map of
# the image walk (built during the estimator's run, and again from ground truth), a small reproduction
# of the RGBD-VIO paper's Table I (navaid reproduce rgbd-vio-table1 --quick), the Smart Cane paper's
# Table I (A* vs the walking-path generator) with plans on the real Willow office map, narrated
# offline routes on real OpenStreetMap extracts (the Berlin one spoken and felt through the cue
# scheduler: cues.csv, cues.png, speech.wav) and the route2 scenario's OSM export, and a summary and
# plot of real recorded data from ../shared/data (a GNSS receiver capture and the EuRoC V1_02
# ground truth).
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

echo "== Full-device runs: the Smart Cane down the corridor, W-ROMA's hand guidance to the tagged box"
$NAVAID simulate --scenario corridor --seed 7 --cache "$OUT/render-cache" --out "$OUT/sim-corridor"
$NAVAID run --recording "$OUT/sim-corridor" --device smart-cane --out "$OUT/device-smart-cane"
$NAVAID simulate --scenario lab-walk-1 --seed 7 --set duration=15 --cache "$OUT/render-cache" --out "$OUT/sim-lab-walk-1"
$NAVAID run --recording "$OUT/sim-lab-walk-1" --device w-roma --out "$OUT/device-w-roma"
echo "   reports: $OUT/device-smart-cane/report.html, $OUT/device-w-roma/report.html"

echo "== Simulated walk: route1, head mount, first 40 s with images (render cache in $OUT/render-cache)"
$NAVAID simulate --scenario route1 --mount head --seed 7 --set duration=40 --cache "$OUT/render-cache" \
  --out "$OUT/sim-route1-head"
$NAVAID info "$OUT/sim-route1-head" | tee "$OUT/sim-route1-head-info.txt"
$NAVAID plot "$OUT/sim-route1-head" --out "$OUT/sim-route1-head-track.png"

echo "== Estimator on the 40 s of images with the semantic map built as it goes, and the map from ground truth"
$NAVAID run --recording "$OUT/sim-route1-head" --out "$OUT/run-route1-head" --set mapping.enabled=true
$NAVAID map --recording "$OUT/sim-route1-head" --poses groundtruth --out "$OUT/map-route1-head-groundtruth"

echo "== Simulated walk: the whole of route1 in feature mode"
$NAVAID simulate --scenario route1 --mount head --seed 7 --set simulation.mode=features --out "$OUT/sim-route1-features"
$NAVAID info "$OUT/sim-route1-features" | tee "$OUT/sim-route1-features-info.txt"

echo "== Estimator (sliding window, RGBD-VIO factors) on the whole route, and its evaluation"
$NAVAID run --recording "$OUT/sim-route1-features" --out "$OUT/run-route1"
$NAVAID eval --est "$OUT/run-route1/trajectory.tum" --gt "$OUT/sim-route1-features" --align 4dof \
  --out "$OUT/eval-route1"

echo "== RGBD-VIO Table I, small version: RGBD-VIO vs VINS-Fusion (RGB-D) vs VINS-RGBD on two lab walks"
$NAVAID reproduce rgbd-vio-table1 --quick --jobs 2 --out "$OUT/reproduce-rgbd-vio-table1-quick"

echo "== Smart Cane Table I: A* vs the walking-path generator on office1, office2, pillar, school (30 pairs each)"
$NAVAID reproduce smart-cane-table1 --out "$OUT/reproduce-smart-cane-table1"

echo "== Walking-path generator and A* across the real Willow office map"
$NAVAID plan --map "$DATA/ros-map-willow/willow-full-0.05.yaml" --planner wpg --start 5.6,20,90 --goal 35,40 \
  --out "$OUT/plan-willow-wpg"
$NAVAID plan --map "$DATA/ros-map-willow/willow-full-0.05.yaml" --planner astar --start 5.6,20,90 --goal 35,40 \
  --set planning.grid.base_clearance_m=0.3 --out "$OUT/plan-willow-astar"

echo "== Offline pedestrian routes on real OpenStreetMap extracts (Berlin Siegessaeule, Paris), narrated"
$NAVAID route --osm "$DATA/osm/berlin-siegessaeule.osm.gz" --from 52.5145,13.3480 --to 52.5145,13.3522 \
  --out "$OUT/route-berlin"
$NAVAID route --osm "$DATA/osm/paris_bss.osm.pbf" --from 48.8620,2.3600 --to 48.8660,2.3700 --out "$OUT/route-paris"
$NAVAID scenario-map --scenario route2 --osm --out "$OUT/route2-osm"

echo "== The Berlin route heard and felt: its narration through the cue scheduler to the eLabrador belt, spoken by espeak-ng"
$NAVAID cues --guidance "$OUT/route-berlin/guidance_timeline.csv" --device belt --out "$OUT/cues-berlin"

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
