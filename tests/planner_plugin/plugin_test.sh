#!/usr/bin/env bash
# The planner plugin seam, as a user meets it: builds examples/planner_plugin on its own
# (configure + build against the source tree's headers), runs a small scenario with the
# plugin's GoalBiasRRT beside RRTConnect, checks both planned (collision checks, successes),
# that compare reads the run, and that a bad plugin entry fails the scenario with a one-line
# error naming the file and the key.
#   plugin_test.sh <taskmatrix binary> <source dir>
set -euo pipefail
cli=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

cmake -S "$src/examples/planner_plugin" -B "$work/plugin" -DTASKMATRIX_INCLUDE_DIR="$src" \
  > "$work/configure.log" || { cat "$work/configure.log"; fail "plugin configure"; }
cmake --build "$work/plugin" > "$work/build.log" 2>&1 || { cat "$work/build.log"; fail "plugin build"; }
[ -f "$work/plugin/libgoal_bias_rrt.so" ] || fail "no libgoal_bias_rrt.so"

# The scenario names the plugin relative to its own folder.
mkdir -p "$work/scenarios"
cat > "$work/scenarios/plugin_reach.yaml" <<YAML
name: plugin_reach
program: reach
params: {object: cup}
robots: [tallbot]
environments: [kitchen]
execution: kinematic
obstacles: {count: 4}
planners:
  - RRTConnect
  - {plugin: ../plugin/libgoal_bias_rrt.so, name: GoalBiasRRT, params: {goal_bias: 0.2}}
layout_seed: 3
seed: 1
trials: 2
time_limit_s: 30
success: graspable(cup)
YAML
"$cli" run "$work/scenarios/plugin_reach.yaml" --jobs 1 --out "$work/run" > "$work/run.log" 2>&1 ||
  { cat "$work/run.log"; fail "run"; }
trials="$work/run/trials.jsonl"
[ "$(grep -c '"planner":"GoalBiasRRT"' "$trials")" = 2 ] || fail "expected 2 GoalBiasRRT trials"
[ "$(grep -c '"planner":"RRTConnect"' "$trials")" = 2 ] || fail "expected 2 RRTConnect trials"
# Every plugin trial planned: collision checks counted by the backend, and it succeeded.
python3 - "$trials" <<'PY' || fail "plugin trials did not plan or did not succeed"
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
plugin = [r for r in rows if r["planner"] == "GoalBiasRRT"]
assert all(r["collision_checks"] > 0 for r in plugin), [r["collision_checks"] for r in plugin]
assert all(r["success"] for r in plugin), [r.get("failure_reason") for r in plugin]
PY
# The same run twice plans the same paths (seeded, bounded by iterations).
"$cli" run "$work/scenarios/plugin_reach.yaml" --jobs 1 --out "$work/run2" > /dev/null 2>&1 ||
  fail "second run"
"$cli" compare "$work/run" "$work/run2" --exact-work --fail-on-regression --fail-on-unpaired \
  --report "$work/compare" > "$work/compare.log" 2>&1 || { cat "$work/compare.log"; fail "compare"; }
grep -q "GoalBiasRRT" "$work/compare/compare.md" || fail "compare.md does not list GoalBiasRRT"
grep -q "GoalBiasRRT" "$work/run/planners.md" || fail "planners.md does not compare GoalBiasRRT"

# Bad plugin entries: exit status 2, one line naming the scenario file and the key.
expect_error() {  # <yaml planners line> <text the error must contain>
  sed "s|^  - {plugin.*|  - $1|" "$work/scenarios/plugin_reach.yaml" > "$work/scenarios/bad.yaml"
  set +e
  "$cli" validate "$work/scenarios/bad.yaml" > "$work/bad.log" 2>&1
  local rc=$?
  set -e
  [ "$rc" = 2 ] || { cat "$work/bad.log"; fail "exit $rc for $1"; }
  grep -q "bad.yaml" "$work/bad.log" || { cat "$work/bad.log"; fail "no file name for $1"; }
  grep -q -- "$2" "$work/bad.log" || { cat "$work/bad.log"; fail "no '$2' for $1"; }
}
expect_error "{plugin: ../plugin/libnone.so, name: GoalBiasRRT}" "does not exist"
echo 'int taskmatrix_unrelated = 1;' > "$work/none.cc"
c++ -shared -fPIC "$work/none.cc" -o "$work/plugin/libempty.so"
expect_error "{plugin: ../plugin/libempty.so, name: GoalBiasRRT}" "does not define taskmatrix_planner_plugin_api"
expect_error "{plugin: ../plugin/libgoal_bias_rrt.so, name: Other}" "registers no 'Other'"
expect_error "{plugin: ../plugin/libgoal_bias_rrt.so, name: GoalBiasRRT, params: {bias: 1}}" "parameter 'bias' is unknown"
expect_error "{plugin: ../plugin/libgoal_bias_rrt.so, name: GoalBiasRRT, params: {goal_bias: high}}" "is not a finite number"
expect_error "{plugin: ../plugin/libgoal_bias_rrt.so, name: GoalBiasRRT, params: {goal_bias: 2}}" "must be in \[0, 1\]"
echo "plugin test passed"
