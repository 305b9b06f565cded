#!/usr/bin/env bash
# A small ablation study run three ways, whose results.csv must agree (docs/cluster.md): the local
# engine, Snakemake on this machine, and Snakemake on a real single-node Slurm cluster started here
# (scripts/slurm-local.sh: munged, slurmctld, slurmd) and stopped at the end. Then the Slurm study
# again: finished cells are resumed, failing ones retried.
# Usage: slurm_study.sh NAVAID WORK_DIR
set -euo pipefail
if [ "$(id -u)" -ne 0 ] && [ "${CI:-}" != "true" ]; then
  echo "slurm_study: skipped: slurmd needs root (CI runs it as root)"
  exit 77
fi
navaid=$1
work=$(realpath -m "$2")
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
rm -rf "$work"
mkdir -p "$work"
trap 'bash "$source_dir/scripts/slurm-local.sh" stop "$work/slurm"' EXIT
eval "$(bash "$source_dir/scripts/slurm-local.sh" start "$work/slurm")"
sinfo

cat > "$work/matrix.yaml" <<'YAML'
recordings:
  - name: corridor
    simulate: {scenario: corridor, set: [simulation.mode=features, duration=4]}
variants:
  - name: rgbd-vio
  - name: vio
    set: [estimator.depth.enabled=false]
  - name: broken
    set: [estimator.no_such_key=1]
seeds: [1, 2]
metrics: [ate.rmse_m, frames]
YAML

fail() { echo "slurm_study: $*" >&2; exit 1; }
# The three study folders have names of one length: the VIO cells' last digits depend on the
# lengths of the paths they are given (docs/cluster.md, "Same table").
"$navaid" ablate "$work/matrix.yaml" --out "$work/study-local" --jobs 2 --no-plot
"$navaid" ablate "$work/matrix.yaml" --out "$work/study-smake" --jobs 2 --no-plot --engine snakemake
"$navaid" ablate "$work/matrix.yaml" --out "$work/study-slurm" --jobs 4 --no-plot --engine snakemake \
  --profile "$source_dir/experiments/workflow/slurm" | tee "$work/slurm-run.txt"

# Every column but the wall time.
table() { cut -d, -f1-4,6- "$1/results.csv"; }
for engine in smake slurm; do
  diff <(table "$work/study-local") <(table "$work/study-$engine") || fail "study-$engine/results.csv differs from the local engine's"
done
grep -q "corridor,broken,1,failed" "$work/study-slurm/results.csv" || fail "the failing cell is not reported failed"
grep -q "corridor,vio,2,done" "$work/study-slurm/results.csv" || fail "a cell is not done"
# The jobs really went through Slurm: one batch log per job (2 recordings + 6 cells).
jobs=$(find "$work/study-slurm/workflow/logs" -name 'slurm-*.out' | wc -l)
[ "$jobs" -eq 8 ] || fail "expected 8 Slurm job logs, found $jobs"
grep -q "6 cells: 4 run, 0 resumed, 2 failed" "$work/slurm-run.txt" || fail "unexpected summary line"

# Again on Slurm: the four finished cells resume, the two failing ones run (and fail) again.
"$navaid" ablate "$work/matrix.yaml" --out "$work/study-slurm" --jobs 4 --no-plot --engine snakemake \
  --profile "$source_dir/experiments/workflow/slurm" | tee "$work/slurm-again.txt"
grep -q "6 cells: 0 run, 4 resumed, 2 failed" "$work/slurm-again.txt" || fail "the second run did not resume"
jobs=$(find "$work/study-slurm/workflow/logs" -name 'slurm-*.out' | wc -l)
[ "$jobs" -eq 10 ] || fail "expected 2 more Slurm jobs (the failing cells), found $jobs logs in all"
echo "slurm_study: the local, Snakemake and Slurm engines give the same table; resuming works"
