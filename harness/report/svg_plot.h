// Plots as inline SVG text for the self-contained HTML reports (harness/compare/html_report.h):
// distributions (box and points) on a log axis, rates with intervals, and paired scatter.
#pragma once

#include <string>
#include <vector>

namespace taskmatrix::harness {

// Escapes &, <, >, " and ' for HTML text and attributes.
std::string html_escape(const std::string& s);

// A distinct colour for series `i` (base runs are grey: kBaseColour).
std::string series_colour(int i);
inline constexpr const char* kBaseColour = "#8c8c8c";

struct DistributionRow {
  std::string label;
  std::string colour;
  std::vector<double> values;  // positive values only are drawn (log axis)
};
// One horizontal row per entry: a box (quartiles, median) over the points (jittered
// deterministically), on a shared logarithmic x axis labelled `axis`.
std::string svg_distributions(const std::vector<DistributionRow>& rows, const std::string& axis);

struct IntervalPoint {
  int series = 0;  // index into the series names
  double value = 0, low = 0, high = 0;
};
struct IntervalRow {
  std::string label;
  std::vector<IntervalPoint> points;
};
struct SeriesName {
  std::string name, colour;
};
// One row per entry with one dot and interval per series, x from 0 to 1 shown as percent.
std::string svg_intervals(const std::vector<IntervalRow>& rows,
                          const std::vector<SeriesName>& series, const std::string& axis);

struct ChangeRow {
  std::string label;
  double value = 0, low = 0, high = 0;  // a change and its interval (NaN: no interval)
  int tone = 0;                         // 1 better (green), -1 worse (red), 0 neither (grey)
};
// One row per entry: a dot and its interval on a linear axis symmetric about 0 (a forest
// plot), labelled `axis`.
std::string svg_changes(const std::vector<ChangeRow>& rows, const std::string& axis);

struct ScatterPoint {
  double x = 0, y = 0;
  int series = 0;
  std::string title;  // tooltip
};
// Log-log scatter of positive pairs with the diagonal y = x.
std::string svg_scatter(const std::vector<ScatterPoint>& points,
                        const std::vector<SeriesName>& series, const std::string& x_axis,
                        const std::string& y_axis);

}  // namespace taskmatrix::harness
