#!/usr/bin/env bash
# Set up treelearn on a fresh Debian 12 machine: install the Debian packages it needs
# (idempotent; runs as root, or with sudo), then configure and build build/treelearn.
# Usage: scripts/setup.sh [--no-build] [--asan]
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake pkg-config git
  libbullet-dev libbox2d-dev libeigen3-dev liburdfdom-dev libtinyxml2-dev
  libosmesa6-dev libpng-dev libstb-dev
  libtomlplusplus-dev libcli11-dev libonnx-dev libprotobuf-dev protobuf-compiler
  libgtest-dev libgmock-dev libbenchmark-dev
  ffmpeg clang-format python3-matplotlib
  openmpi-bin libopenmpi-dev
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo_cmd apt-get update -qq
  $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
  echo "setup: all Debian packages present"
fi

build=1; asan=OFF
for a in "$@"; do
  case "$a" in
    --no-build) build=0 ;;
    --asan) asan=ON ;;
    *) echo "setup: unknown option '$a' (use --no-build or --asan)" >&2; exit 2 ;;
  esac
done
if ((build)); then
  dir=build; [ "$asan" = ON ] && dir=build-asan
  # MPI in the plain build (training under mpirun); the sanitizer build leaves it out: Open MPI keeps allocations to
  # its exit that LeakSanitizer would report in every test
  mpi=ON; [ "$asan" = ON ] && mpi=OFF
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release -DTREELEARN_SANITIZE="$asan" -DTREELEARN_MPI="$mpi" >/dev/null
  cmake --build "$dir" -j"$(nproc)"
fi
