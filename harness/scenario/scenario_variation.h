// The scenario keys that vary a trial's world (scenarios/README.md, "Task variations" and
// "Obstacles that matter"): `objects:`, `surfaces:`, `robot_start:` and the targeted obstacle
// keys `obstacles.near | path | overhead | floor`. Read and checked when the file is read
// (types, ranges, and names against every environment the scenario lists); every value is
// drawn per layout seed by the backend (Scene::make_trial_layout).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "taskmatrix/core/environment_spec.h"
#include "taskmatrix/core/obstacle_layout.h"
#include "taskmatrix/core/task_variation.h"
#include "taskmatrix/io/yaml_reader.h"

namespace taskmatrix::harness {

// Lines of the keys read, by dotted key ("objects.cup.on"), for errors found when drawing.
using KeyLines = std::map<std::string, int>;

// `objects:`, `surfaces:` and `robot_start:` of a scenario's root (absent keys: nothing).
core::VariationOptions read_variation(const io::YamlNode& root, KeyLines& lines);

// `near`, `path`, `overhead`, `floor` of a scenario's `obstacles:` (each a map or a list of
// maps), appended to options.targeted.
void read_targeted_obstacles(const io::YamlNode& obstacles, core::ObstacleOptions& options,
                             KeyLines& lines);

// The line of `key`, or of the nearest enclosing key that was read; 0 if none.
int line_of(const KeyLines& lines, const std::string& key);

}  // namespace taskmatrix::harness
