// One table for both report formats: the same rows as a Markdown table (for compare.md,
// planners.md) and as an HTML table (report.html, planners.html). Cells are plain text; each
// writer escapes what its format needs.
#pragma once

#include <string>
#include <vector>

namespace taskmatrix::harness {

struct ReportTable {
  struct Row {
    std::vector<std::string> cells;
    std::string tone;  // "", "bad" or "good": how the HTML row is shaded
  };
  std::vector<std::string> columns;
  std::vector<Row> rows;
};

// "| a | b |\n|---|---|\n..." with '|' and line breaks in cells escaped.
std::string markdown_table(const ReportTable& table);
// "<table>...</table>" with every cell HTML-escaped.
std::string html_table(const ReportTable& table);

}  // namespace taskmatrix::harness
