#!/usr/bin/env bash
# Runs every libFuzzer harness (tests/fuzz) for SECONDS each (default 60), two at a time.
# Usage: scripts/fuzz.sh [SECONDS] [HARNESS...]
# Corpora grow in $NAVAID_FUZZ_DIR (default build-sanitize/fuzz) and are reused by the next run;
# every run's executions and time are appended to fuzz-log.csv there, so CPU time adds up across
# runs. A crash, hang (> 25 s on one input), leak or escaped exception fails the script and leaves
# the input in artifacts/<harness>/, with the command that replays it.
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_EACH=${1:-60}
shift || true
[[ "$SECONDS_EACH" =~ ^[0-9]+$ ]] || { echo "fuzz.sh: SECONDS must be a whole number, got '$SECONDS_EACH'" >&2; exit 2; }
BUILD=${NAVAID_SANITIZE_BUILD:-build-sanitize}
DIR=${NAVAID_FUZZ_DIR:-$BUILD/fuzz}
DATA=${NAVAID_DATA:-../shared/data}
JOBS=${NAVAID_FUZZ_JOBS:-2}
[ -d "$DATA" ] || { echo "fuzz.sh: no data sets at $DATA (set NAVAID_DATA)" >&2; exit 2; }

# NAVAID_FUZZ_SIMULATED_SEEDS=0: seeds from the data sets and fixtures only (no navaid build).
SIMULATED=${NAVAID_FUZZ_SIMULATED_SEEDS:-1}
HARNESSES=("$@")
ALL=($(sed -n 's/^navaid_add_fuzzer(\(fuzz_[a-z_]*\).*/\1/p' tests/fuzz/CMakeLists.txt | sort))
[ ${#HARNESSES[@]} -gt 0 ] || HARNESSES=("${ALL[@]}")
for h in "${HARNESSES[@]}"; do
  [[ " ${ALL[*]} " == *" $h "* ]] || { echo "fuzz.sh: no harness '$h' (have: ${ALL[*]})" >&2; exit 2; }
done
targets=("${HARNESSES[@]}")
[ "$SIMULATED" = 0 ] || targets+=(navaid)

bash scripts/install-deps.sh --sanitizers
bash scripts/sanitize-build.sh "${targets[@]}"

# Seeds: real data, fixtures, and small recordings the simulator writes once (features and images).
mkdir -p "$DIR"
export ASAN_OPTIONS=detect_leaks=0  # the simulator is not what is being fuzzed
recordings=()
if [ "$SIMULATED" != 0 ] && [ ! -f "$DIR/recordings/.done" ]; then
  rm -rf "$DIR/recordings"
  "$BUILD/apps/navaid" simulate --scenario route1 --seed 1 --threads 1 --out "$DIR/recordings/route1-features" \
    --set simulation.mode=features --set duration=1 >/dev/null
  "$BUILD/apps/navaid" simulate --scenario lab-walk-1 --mount hand --seed 1 --threads 1 \
    --out "$DIR/recordings/lab-walk-1-images" --set duration=0.2 --set sensor.camera.resolution=[32,24] >/dev/null
  touch "$DIR/recordings/.done"
fi
[ "$SIMULATED" = 0 ] || recordings=(--recording "$DIR/recordings/route1-features" --recording "$DIR/recordings/lab-walk-1-images")
unset ASAN_OPTIONS
rm -rf "$DIR/seeds"
/usr/bin/env python3 tests/fuzz/make_seeds.py --data "$DATA" --source . --out "$DIR/seeds" "${recordings[@]}" >/dev/null

run_one() {
  local h=$1 secs=$2 build=$3 dir=$4
  mkdir -p "$dir/corpus/$h" "$dir/artifacts/$h" "$dir/seeds/$h" "$dir/logs"
  local dict=()
  [ -f "tests/fuzz/$h.dict" ] && dict=(-dict="tests/fuzz/$h.dict")
  local start rc=0
  start=$(date +%s)
  ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 UBSAN_OPTIONS=print_stacktrace=1 \
    "$build/tests/fuzz/$h" -max_total_time="$secs" -timeout=25 -rss_limit_mb=4096 -print_final_stats=1 \
    -artifact_prefix="$dir/artifacts/$h/" "${dict[@]}" "$dir/corpus/$h" "$dir/seeds/$h" \
    >"$dir/logs/$h.log" 2>&1 || rc=$?
  local execs cov
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$dir/logs/$h.log" | grep -o '[0-9]*$' || echo 0)
  cov=$(grep -o 'cov: [0-9]*' "$dir/logs/$h.log" | tail -1 | grep -o '[0-9]*' || echo 0)
  echo "$(date -u +%FT%TZ),$h,$(( $(date +%s) - start )),${execs:-0},${cov:-0},$rc" >>"$dir/fuzz-log.csv"
  if [ "$rc" -ne 0 ]; then
    echo "FAIL $h (exit $rc): $(grep -m1 -E 'ERROR|==[0-9]+==|unclear error|disagree|broke' "$dir/logs/$h.log" || true)"
    echo "     input: $(ls -t "$dir/artifacts/$h" | head -1 | sed "s|^|$dir/artifacts/$h/|")"
    echo "     replay: $build/tests/fuzz/$h <input>    log: $dir/logs/$h.log"
    return 1
  fi
  echo "ok   $h: ${execs:-0} inputs in $(( $(date +%s) - start )) s, coverage ${cov:-0}"
}
export -f run_one
[ -f "$DIR/fuzz-log.csv" ] || echo "utc,harness,seconds,executions,coverage,exit" >"$DIR/fuzz-log.csv"
echo "fuzz.sh: ${#HARNESSES[@]} harnesses x ${SECONDS_EACH} s, $JOBS at a time, corpora in $DIR"
status=0
printf '%s\n' "${HARNESSES[@]}" | xargs -P "$JOBS" -I{} bash -c 'run_one "$@"' _ {} "$SECONDS_EACH" "$BUILD" "$DIR" || status=1
awk -F, 'NR > 1 { t[$2] += $3 } END { for (h in t) printf "fuzz.sh: %s: %.2f CPU-hours in all runs\n", h, t[h] / 3600 }' \
  "$DIR/fuzz-log.csv" | sort
exit $status
