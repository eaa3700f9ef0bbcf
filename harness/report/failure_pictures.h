// Pictures of a failed trial for reports (harness/replay/trial_video.h draws them; the
// comparison's report.html shows them). Plain data: PNG file bytes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace taskmatrix::harness {

// A failed trial at the moment it failed: the overview (options.camera) and a close-up aimed at
// what was moving there, for reports.
struct FailurePictures {
  std::vector<std::uint8_t> overview, close_up;  // PNG file bytes
  double time_s = 0;                             // simulated time of the frame shown
  std::string close_up_camera;                   // the close-up as a --camera value (lookat:...)
  std::string focus;  // what the close-up looks at: "right hand (r_palm) at cup", ...
};

}  // namespace taskmatrix::harness
