#!/usr/bin/env bash
# README command 1: install what is missing, build Release, run the main job: the default
# suite (every task program, both humanoids, both environments, randomized layouts) with
# two worker processes. Results: results/runs/default/ (summary.md, trials.jsonl, ompl.log, ...).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
build/bin/taskmatrix run scenarios/suites/default.yaml --jobs "${TASKMATRIX_JOBS:-2}"
