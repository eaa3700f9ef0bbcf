// A compact recording of a skillset's simulated state at a fixed rate, for replays and videos
// (core::Skillset::record_states). The numbers per frame are the backend's state vector (the
// MuJoCo backend: every generalized position, robot, objects and visitor), stored as float.
#pragma once

#include <cstddef>
#include <vector>

namespace taskmatrix::core {

struct StateRecording {
  int nq = 0;  // numbers per frame
  double frame_period_s = 0;
  std::vector<double> times;  // one per frame
  std::vector<float> qpos;    // frames x nq
  // Things the backend took out of the world (debris a tool collected), by the backend's
  // index of the body; they are moved in its model, not in the state vector.
  struct Removal {
    double time_s;
    int body;
  };
  std::vector<Removal> removals;
  size_t frames() const { return times.size(); }
};

}  // namespace taskmatrix::core
