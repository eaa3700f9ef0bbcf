// `taskmatrix check-robot NAME`: what a user runs when adding a robot. It loads the robot in
// every environment (the loader's checks: profile keys and names, joint limits, postures,
// canned motions, the head camera), lints the profile against the model by forward kinematics
// (mujoco/robot_check.h: postures, mirror signs, palm axes, fingers, reach envelope against
// every environment's surfaces), and, when the lint finds no error, runs the twelve program
// scenarios of scenarios/suites/default.yaml (under the models' root, else the built-in one)
// once in one environment through the scenario runner, printing one line per program.
//
// Exit status: 0 no lint error and every program succeeded; 1 a lint error (nothing run);
// 4 no lint error but a program failed; 2 bad input (unknown names, options); 130 interrupted.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>

#include "harness/scenario/model_catalog.h"
#include "taskmatrix/core/task_program.h"

namespace taskmatrix::harness {

struct CheckRobotOptions {
  std::string robot;
  std::string environment;    // of the quick run; empty: kitchen if there is one, else the first
  bool run = true;            // false: the lint only
  std::filesystem::path out;  // run directory; empty: results/runs/check-robot-<robot>-<env>
  int jobs = 2;
};

inline constexpr int kCheckRobotLintError = 1;
inline constexpr int kCheckRobotProgramFailed = 4;

int run_check_robot(const ModelCatalog& catalog, core::ProgramRegistry& registry,
                    const CheckRobotOptions& options, std::ostream& out, std::ostream& err);

}  // namespace taskmatrix::harness
