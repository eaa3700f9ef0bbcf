#!/usr/bin/env bash
# README command 1: install what is missing, build Release, run the main job.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
build/bin/taskmatrix scenes --seeds 3 --out results/scenes
