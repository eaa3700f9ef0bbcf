// Sections of the comparison reports beyond the verdict tables, as one table model for both
// Markdown (compare.md, planners.md) and HTML (report.html, planners.html): paired path
// quality, statistical power, failures by group and the trials whose outcome changed.
#pragma once

#include <string>

#include "harness/compare/compare.h"
#include "harness/report/report_table.h"

namespace taskmatrix::harness {

// "reach · tallbot · kitchen · RRTConnect" ("RRTConnect -> BITstar" for two planners).
std::string group_name(const PairedGroup& g);

// Every measure of the pooled pairs, then each group's measured ones.
ReportTable path_quality_table(const Comparison& c);
// Per group (and pooled): pairs, base success, the smallest detectable success change and
// planning-time ratio, and the trials needed for the power targets.
ReportTable power_table(const Comparison& c);
// Per group and run: each failure (where it failed: why) with its count.
ReportTable failures_table(const Comparison& c);
// The trials whose outcome changed, with where and why the failing one failed.
ReportTable flips_table(const Comparison& c);

// One paragraph each: how the path quality and the power are computed.
std::string path_quality_method(const Comparison& c);
std::string power_method(const Comparison& c);

// The sections "Path quality", "Statistical power" and "Failures by group" in Markdown.
std::string comparison_sections_markdown(const Comparison& c);

}  // namespace taskmatrix::harness
