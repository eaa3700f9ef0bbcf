// LineConnect, the project's own planner over the core planning interface: the straight line
// from the start to each goal first (in the goals' order), then a bidirectional RRT-Connect
// (one tree from the start, one from every goal; extend one towards a random state, connect
// the other to the new state, swap), then shortcutting of the path. Deterministic by seed (its
// own generator, std::mt19937_64) and bounded by the problem's iterations: one iteration is one
// random state drawn (or one straight line tried).
//
// Parameters: range (m or rad, the longest step of an extension; 0: a fifth of the space's
// extent, as OMPL's RRTConnect), straight_line_first (bool, default true), shortcuts (random
// shortcut attempts per simplification round, default 20).
#pragma once

#include "taskmatrix/core/motion_planning.h"

namespace taskmatrix::planners {

// Adds LineConnect to `registrar`.
void register_planners(core::PlannerRegistrar& registrar);

}  // namespace taskmatrix::planners
