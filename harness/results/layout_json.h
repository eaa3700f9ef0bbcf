// A trial's drawn world as JSON: the `layout` field of a trials.jsonl line and the `variation`
// of a trajectory file's header. Every drawn value is kept at full precision, so a trial can be
// understood (and its world rebuilt) from the record alone.
//
//   {"obstacles": [{"shape": "box", "group": "obstacles near cup", "position": [x, y, z],
//                   "yaw": r, "size": [a, b, c], "hanging": false}, ...],
//    "surfaces": {"work_surface": {"height_m": 0.71, "shift_m": 0.06}},
//    "objects": {"cup": {"on": "work_surface", "x": .., "y": .., "z": .., "yaw": ..}},
//    "robot_start": {"x": .., "y": .., "yaw": ..}, "draw": 1}
// `group` is absent for the random obstacles; surfaces, objects and robot_start are absent
// when the scenario does not vary them; `draw` (core::draw_world) when it is the first.
#pragma once

#include <nlohmann/json.hpp>

#include "taskmatrix/core/task_variation.h"

namespace taskmatrix::harness {

nlohmann::json variation_json(const core::TaskVariation& variation);
// Throws std::runtime_error (from nlohmann) for a malformed object.
core::TaskVariation variation_from_json(const nlohmann::json& json);
nlohmann::json layout_json(const core::TrialLayout& layout);

}  // namespace taskmatrix::harness
