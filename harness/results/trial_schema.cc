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

// A field the reports show has a label; a table column has a format; summary.md's column is a
// statistic of summary.json; compare's per-group columns are the work counts it totals; a
// path-quality measure has the words of its findings.
constexpr bool displays_complete() {
  for (const TrialField& f : kTrialFields) {
    const FieldDisplay& d = f.display;
    const bool shown = !d.summary_md.empty() || d.compare_groups || d.planner_table ||
                       d.path_quality != Better::kNone;
    if (shown && d.label.empty()) return false;
    if ((!d.summary_md.empty() || d.planner_table || d.compare_groups) && d.format.empty()) {
      return false;
    }
    if (!d.summary_md.empty() && f.summary == FieldSummary::kNone) return false;
    if (d.compare_groups && !f.exact_work) return false;
    if ((d.path_quality != Better::kNone) != !d.better_word.empty()) return false;
    if (d.better_word.empty() != d.worse_word.empty()) return false;
  }
  return true;
}
static_assert(displays_complete(),
              "kTrialFields: a field shown without a label or format, a summary.md column "
              "summary.json lacks, a compared column that is no work count, or a path-quality "
              "measure without its words");

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

// Where the reports show a field, for the docs' table.
std::string shown_in(const FieldDisplay& d) {
  std::string out;
  const auto add = [&out](const std::string& where) { out += (out.empty() ? "" : ", ") + where; };
  if (!d.summary_md.empty()) add("summary.md (" + std::string(d.summary_md) + ")");
  if (d.compare_groups) add("compare per group");
  if (d.planner_table) add("planners' tables");
  if (d.path_quality != Better::kNone) {
    add(std::string("path quality (") + (d.path_quality == Better::kLower ? "lower" : "higher") +
        " is better: " + std::string(d.better_word) + ")");
  }
  return out;
}

}  // namespace

const std::vector<std::string>& timing_fields() {
  static const std::vector<std::string> fields = [] {
    std::vector<std::string> out;
    for (const TrialField& f : kTrialFields) {
      if (f.timing) out.emplace_back(f.name);
    }
    return out;
  }();
  return fields;
}

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
      "count | holds | reports call it | shown in |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const TrialField& f : kTrialFields) {
    const std::string property = f.ompl_property.empty() ? ""
                                                         : std::string(f.ompl_property) + " (" +
                                                               to_string(f.ompl_type) + ")";
    std::string label(f.display.label);
    if (!f.display.unit.empty()) label += " [" + std::string(f.display.unit) + "]";
    if (!f.display.format.empty()) label += " `" + std::string(f.display.format) + "`";
    md += "| `" + std::string(f.name) + "` | " + std::string(f.unit) + " | " +
          source_text(f.source) + " | " + (f.timing ? "yes" : "") + " | " +
          summary_text(f.summary) + " | " + property + " | " + (f.exact_work ? "yes" : "") + " | " +
          std::string(f.doc) + " | " + label + " | " + shown_in(f.display) + " |\n";
  }
  return md;
}

}  // namespace taskmatrix::harness
