// OMPL's geometric planners as core planners (taskmatrix/core/motion_planning.h): BiEST,
// BITstar, BKPIECE1, EST, KPIECE1, LazyPRM, PRM, RRT, RRTConnect, RRTstar, SBL, each with
// OMPL's own parameters by OMPL's names (e.g. range), on a real vector space with the
// problem's bounds, validity callback and motion resolution, followed by path simplification
// bounded by work.
//
// Determinism: OMPL seeds every RNG from one process-global generator. solve() reseeds it with
// the problem's seed and holds a process-wide lock while planning, so the same problem and seed
// give the same path bit for bit whatever was planned before in the process. Under an
// iteration budget the result does not depend on the machine or its load either:
// simplification is bounded by rounds, PRM runs in one thread (OMPL's polls for solutions from
// a second thread), and the clock bounds are safety nets whose firing the result reports.
#pragma once

#include "taskmatrix/core/motion_planning.h"

namespace taskmatrix::ompl_planners {

// Adds OMPL's planners to `registrar` (names above).
void register_planners(core::PlannerRegistrar& registrar);

}  // namespace taskmatrix::ompl_planners
