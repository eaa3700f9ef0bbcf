// The main job until the scenario runner exists: every robot in every environment over a few
// layout seeds, each loaded, laid out, checked for robot contacts at rest and rendered from
// the environment's overview camera and the robot's head camera, with a printed table.
#pragma once

#include <filesystem>
#include <ostream>

#include "harness/scenario/model_catalog.h"

namespace taskmatrix::harness {

struct ScenesJobOptions {
  int seeds = 3;      // layout seeds 1..seeds
  int obstacles = 8;  // per layout
  int width = 960;
  int height = 720;
  std::filesystem::path out = "results/scenes";
};

// Returns the number of scenes in which the robot touched something at rest (0 is healthy).
int run_scenes_job(const ModelCatalog& catalog, const ScenesJobOptions& options, std::ostream& out);

}  // namespace taskmatrix::harness
