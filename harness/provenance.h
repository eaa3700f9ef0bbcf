// provenance.json: what produced a run, so that two runs can be compared honestly: the git
// commit (and whether the tree had changes), MuJoCo and OMPL versions, compiler, host (name,
// CPU model, cores, memory), the SHA-256 of the scenario files, seeds and overrides, the
// command line, and when it ran.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/scenario.h"

namespace taskmatrix::harness {

// SHA-256 (hex) of the run plan's files: the suite file and every scenario file, each as
// its path relative to the plan's folder and its bytes.
std::string plan_hash(const RunPlan& plan);

std::string host_name();
std::string cpu_model();  // /proc/cpuinfo's model name
std::string utc_now_iso();
// From OMPL's version macros (Debian's OMPL_VERSION string is empty), e.g. "1.5.2".
std::string ompl_version();
std::string mujoco_version();  // e.g. "2.2.2"

nlohmann::json make_provenance(const RunPlan& plan, const std::filesystem::path& repo_root,
                               const std::vector<std::string>& command_line, int jobs);

}  // namespace taskmatrix::harness
