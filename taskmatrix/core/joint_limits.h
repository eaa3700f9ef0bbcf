// How far past a joint's limit a value may lie, and what becomes of it: three tolerances for
// three different reasons, used by every backend and by the core.
#pragma once

namespace taskmatrix::core {

// Rounding: a value of a query or a file (an IK or plan goal, a configuration to check, a
// profile posture) this close past a limit (rad or m) counts as within it, since arithmetic
// on the limit's value rounds. Paths and commands are still clamped to the limit itself.
inline constexpr double kLimitRounding = 1e-9;

// Commands: a commanded position this close past a limit (rad or m) is clamped to it; further
// is the caller's error (std::invalid_argument).
inline constexpr double kCommandClampTolerance = 1e-6;

// Plan starts: a joint that rests this far past a limit (rad or m), as simulated joints held
// at a limit do (soft limit constraints), is planned from the limit; further, the start is
// invalid (kInvalidStart).
inline constexpr double kStartPastLimit = 0.02;

}  // namespace taskmatrix::core
