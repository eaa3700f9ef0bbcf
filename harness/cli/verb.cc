#include "harness/cli/verb.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "taskmatrix/programs/primitives.h"

namespace taskmatrix::harness::cli {

const ModelCatalog& VerbContext::catalog() {
  if (!catalog_) catalog_.emplace(ModelCatalog::from_environment());
  return *catalog_;
}

core::ProgramRegistry& VerbContext::programs() {
  if (!programs_) {
    programs_.emplace();
    programs::register_programs(*programs_);
  }
  return *programs_;
}

CLI::Validator finite_range(double lo, double hi) {
  auto number = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return std::string(buf);
  };
  const std::string range = "[" + number(lo) + ", " + number(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !std::isfinite(v)) return "must be a finite number";
        return v < lo || v > hi ? "must be in " + range : "";
      },
      "NUMBER in " + range);
}

}  // namespace taskmatrix::harness::cli
