#!/usr/bin/env bash
# Installs navaid's build, test and plotting dependencies from Debian 12 packages.
# Idempotent: packages already present are skipped, so a second run costs a few seconds.
# Usage: install-deps.sh [--sanitizers]
#   --sanitizers  also clang, LLVM and libFuzzer for the sanitizer and fuzzing tree
#                 (scripts/test-sanitizers.sh, scripts/fuzz.sh); the README's commands need none.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config ccache git
  libeigen3-dev
  libyaml-cpp-dev
  libcli11-dev
  libspdlog-dev libfmt-dev
  nlohmann-json3-dev
  libgeographiclib-dev
  libembree-dev
  libopencv-dev
  libceres-dev
  liboctomap-dev libdynamicedt3d-dev
  libpcl-dev
  libvisp-detection-dev libvisp-core-dev libapriltag-dev
  libosmium2-dev libexpat1-dev libbz2-dev zlib1g-dev
  libespeak-ng-dev espeak-ng-data
  libpocketsphinx-dev libsphinxbase-dev pocketsphinx-en-us
  socat
  librosbag-storage-dev libroslz4-dev libsensor-msgs-dev libnav-msgs-dev libgeometry-msgs-dev libtf2-msgs-dev
  libvisualization-msgs-dev
  python3-rosbag python3-roslz4 python3-sensor-msgs python3-geometry-msgs python3-nav-msgs python3-std-msgs
  python3-tf2-msgs python3-visualization-msgs
  snakemake munge slurmctld slurmd slurm-client
  chromium
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-matplotlib python3-numpy
)
if [ "${1:-}" = "--sanitizers" ]; then
  PACKAGES+=(clang clang-14 libfuzzer-14-dev llvm-14)
elif [ $# -gt 0 ]; then
  echo "install-deps: unknown argument '$1' (usage: install-deps.sh [--sanitizers])" >&2
  exit 2
fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "install-deps: missing packages (${missing[*]}) and not root; run as root" >&2
    exit 1
  fi
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
