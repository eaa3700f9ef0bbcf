#include "harness/results/trial_schema.h"

namespace taskmatrix::harness {

namespace {

// Every name once: a field listed twice would be written, summarised or logged twice.
constexpr bool names_unique() {
  for (size_t i = 0; i < kTrialFields.size(); ++i) {
    for (size_t j = i + 1; j < kTrialFields.size(); ++j) {
      if (kTrialFields[i].name == kTrialFields[j].name) return false;
    }
  }
  return true;
}
static_assert(names_unique(), "kTrialFields lists a field twice");

// A property has a type and a type a property; a work count is a count.
constexpr bool consistent() {
  for (const TrialField& f : kTrialFields) {
    if (f.ompl_property.empty() != (f.ompl_type == OmplType::kNone)) return false;
    if (f.exact_work && (f.timing || f.unit != "count")) return false;
  }
  return true;
}
static_assert(consistent(), "kTrialFields: a property without a type, or a timed work count");

const char* source_text(FieldSource s) {
  switch (s) {
    case FieldSource::kIdentity:
      return "identity";
    case FieldSource::kOutcome:
      return "outcome";
    case FieldSource::kMeasured:
      return "measured";
    case FieldSource::kRunner:
      return "runner";
  }
  return "?";
}

const char* summary_text(FieldSummary s) {
  switch (s) {
    case FieldSummary::kNone:
      return "";
    case FieldSummary::kMedian:
      return "median";
    case FieldSummary::kMedianP90:
      return "median, p90";
  }
  return "?";
}

}  // namespace

std::vector<std::string> exact_work_fields() {
  std::vector<std::string> out;
  for (const TrialField& f : kTrialFields) {
    if (f.exact_work) out.emplace_back(f.name);
  }
  return out;
}

const char* to_string(OmplType type) {
  switch (type) {
    case OmplType::kNone:
      return "";
    case OmplType::kReal:
      return "REAL";
    case OmplType::kInteger:
      return "INTEGER";
    case OmplType::kBoolean:
      return "BOOLEAN";
    case OmplType::kEnum:
      return "ENUM";
  }
  return "?";
}

std::string trial_fields_markdown() {
  std::string md =
      "| field | unit | written by | timing | summary.json | ompl.log property | exact work "
      "count | holds |\n|---|---|---|---|---|---|---|---|\n";
  for (const TrialField& f : kTrialFields) {
    const std::string property = f.ompl_property.empty() ? ""
                                                         : std::string(f.ompl_property) + " (" +
                                                               to_string(f.ompl_type) + ")";
    md += "| `" + std::string(f.name) + "` | " + std::string(f.unit) + " | " +
          source_text(f.source) + " | " + (f.timing ? "yes" : "") + " | " +
          summary_text(f.summary) + " | " + property + " | " + (f.exact_work ? "yes" : "") + " | " +
          std::string(f.doc) + " |\n";
  }
  return md;
}

}  // namespace taskmatrix::harness
