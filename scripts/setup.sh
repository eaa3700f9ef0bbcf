#!/usr/bin/env bash
# Installs the Debian packages the build needs (only those missing), then configures and
# builds Release into build/. Idempotent: a second run installs nothing and rebuilds only
# what changed. Usage: scripts/setup.sh [extra cmake -D options...]
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake pkg-config git
  libmujoco-dev libqhull-dev          # MuJoCo 2.2.2; its CMake config names qhull headers
  libompl-dev libboost-serialization-dev libboost-filesystem-dev libboost-system-dev
  libeigen3-dev libyaml-cpp-dev liburdfdom-dev libtinyxml2-dev
  libbenchmark-dev libgtest-dev libgmock-dev
  libosmesa6-dev liblodepng-dev
  libcli11-dev nlohmann-json3-dev zlib1g-dev libssl-dev
  ompl-demos ffmpeg
  slurmctld slurmd slurm-client munge jq   # the local Slurm cluster of scripts/slurm/
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  if [ "$(id -u)" -ne 0 ]; then
    echo "setup: missing packages and not root; run as root or: sudo apt-get install ${missing[*]}" >&2
    exit 1
  fi
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -q
  apt-get install -y -q --no-install-recommends "${missing[@]}"
else
  echo "setup: all ${#packages[@]} packages present"
fi

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build build -j"${TASKMATRIX_JOBS:-2}"
