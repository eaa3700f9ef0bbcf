#include "harness/report/report_table.h"

#include "harness/report/svg_plot.h"

namespace taskmatrix::harness {

namespace {

std::string markdown_cell(const std::string& text) {
  std::string out;
  for (char ch : text) {
    if (ch == '|') {
      out += "\\|";
    } else if (ch == '\n') {
      out += ' ';
    } else {
      out += ch;
    }
  }
  return out;
}

}  // namespace

std::string markdown_table(const ReportTable& table) {
  std::string md = "|";
  std::string rule = "|";
  for (const std::string& c : table.columns) {
    md += " " + markdown_cell(c) + " |";
    rule += "---|";
  }
  md += "\n" + rule + "\n";
  for (const ReportTable::Row& row : table.rows) {
    md += "|";
    for (const std::string& cell : row.cells) md += " " + markdown_cell(cell) + " |";
    md += "\n";
  }
  return md;
}

std::string html_table(const ReportTable& table) {
  std::string h = "<table><tr>";
  for (const std::string& c : table.columns) h += "<th>" + html_escape(c) + "</th>";
  h += "</tr>";
  for (const ReportTable::Row& row : table.rows) {
    h += row.tone.empty() ? "<tr>" : "<tr class='" + html_escape(row.tone) + "'>";
    for (const std::string& cell : row.cells) h += "<td>" + html_escape(cell) + "</td>";
    h += "</tr>";
  }
  return h + "</table>";
}

}  // namespace taskmatrix::harness
