// The MuJoCo backend's records: the skillset's WorkRecord (core/work_record.h) and a compact
// recording of the simulated state, for replays.
#pragma once

#include <vector>

#include "taskmatrix/core/work_record.h"

namespace taskmatrix::mujoco {

using core::path_digest;
using core::PlanCallRecord;
using core::WorkRecord;

// The simulated state at a fixed rate: every generalized position (robot, objects, visitor)
// as float, and the times debris flakes were removed (they are moved in the model, not qpos).
struct StateRecording {
  int nq = 0;
  double frame_period_s = 0;
  std::vector<double> times;  // one per frame
  std::vector<float> qpos;    // frames x nq
  struct Removal {
    double time_s;
    int body;
  };
  std::vector<Removal> removals;
  size_t frames() const { return times.size(); }
};

}  // namespace taskmatrix::mujoco
