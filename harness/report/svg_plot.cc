#include "harness/report/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "harness/results/summary.h"

namespace taskmatrix::harness {

std::string html_escape(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string series_colour(int i) {
  static const char* const kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                                         "#ff7f0e", "#17becf", "#e377c2", "#bcbd22"};
  return kPalette[static_cast<size_t>(std::max(0, i)) % 8];
}

namespace {

std::string num(double v) { return format_number("%.1f", v); }

std::string tick_label(double v) {
  char buf[32];
  if (v >= 1) {
    std::snprintf(buf, sizeof buf, "%g", v);
  } else {
    std::snprintf(buf, sizeof buf, "%.3g", v);
  }
  return buf;
}

// A log axis covering [lo, hi] (positive), widened to whole decades.
struct LogAxis {
  double lo_exp = -3, hi_exp = 0;
  double x0 = 0, x1 = 1;  // pixel range
  double operator()(double v) const {
    const double e = std::log10(v);
    return x0 + (e - lo_exp) / (hi_exp - lo_exp) * (x1 - x0);
  }
};

LogAxis log_axis(double lo, double hi, double x0, double x1) {
  LogAxis a;
  if (!(lo > 0) || !std::isfinite(lo) || !(hi > 0) || !std::isfinite(hi)) {
    lo = 1e-3;
    hi = 1;
  }
  a.lo_exp = std::floor(std::log10(lo));
  a.hi_exp = std::ceil(std::log10(hi));
  if (a.hi_exp <= a.lo_exp) a.hi_exp = a.lo_exp + 1;
  a.x0 = x0;
  a.x1 = x1;
  return a;
}

// Decade ticks and grid lines of a horizontal log axis at y = `base`, grid up to `top`.
std::string log_ticks_x(const LogAxis& a, double top, double base) {
  std::string s;
  for (double e = a.lo_exp; e <= a.hi_exp + 1e-9; e += 1) {
    const double v = std::pow(10.0, e);
    const double x = a(v);
    s += "<line x1='" + num(x) + "' y1='" + num(top) + "' x2='" + num(x) + "' y2='" + num(base) +
         "' stroke='#ddd'/>";
    s += "<text x='" + num(x) + "' y='" + num(base + 14) +
         "' text-anchor='middle' font-size='11'>" + tick_label(v) + "</text>";
  }
  return s;
}

// A deterministic jitter in [-1, 1] for point i.
double jitter(size_t i) {
  const double golden = 0.6180339887498949;
  const double f = std::fmod(static_cast<double>(i) * golden, 1.0);
  return 2.0 * f - 1.0;
}

std::string svg_open(double w, double h) {
  return "<svg xmlns='http://www.w3.org/2000/svg' width='" + num(w) + "' height='" + num(h) +
         "' viewBox='0 0 " + num(w) + " " + num(h) + "' font-family='sans-serif' role='img'>";
}

std::string legend(const std::vector<SeriesName>& series, double x, double y) {
  std::string s;
  for (const SeriesName& n : series) {
    s += "<circle cx='" + num(x) + "' cy='" + num(y - 4) + "' r='5' fill='" + n.colour + "'/>";
    s += "<text x='" + num(x + 9) + "' y='" + num(y) + "' font-size='12'>" + html_escape(n.name) +
         "</text>";
    x += 24 + 7.0 * static_cast<double>(n.name.size());
  }
  return s;
}

}  // namespace

std::string svg_distributions(const std::vector<DistributionRow>& rows, const std::string& axis) {
  const double label_w = 230, plot_w = 560, row_h = 34, top = 10;
  const double h = top + row_h * static_cast<double>(rows.size()) + 40;
  double lo = INFINITY, hi = 0;
  for (const DistributionRow& r : rows) {
    for (double v : r.values) {
      if (v > 0 && std::isfinite(v)) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
    }
  }
  const LogAxis a = log_axis(lo, hi, label_w, label_w + plot_w);
  const double base = top + row_h * static_cast<double>(rows.size());
  std::string s = svg_open(label_w + plot_w + 20, h);
  s += log_ticks_x(a, top, base);
  for (size_t r = 0; r < rows.size(); ++r) {
    const DistributionRow& row = rows[r];
    const double cy = top + row_h * (static_cast<double>(r) + 0.5);
    std::vector<double> v;
    for (double x : row.values) {
      if (x > 0 && std::isfinite(x)) v.push_back(x);
    }
    s += "<text x='" + num(label_w - 8) + "' y='" + num(cy + 4) +
         "' text-anchor='end' font-size='12'>" + html_escape(row.label) + " (" +
         std::to_string(v.size()) + ")</text>";
    if (v.empty()) continue;
    const double q1 = quantile(v, 0.25), q2 = quantile(v, 0.5), q3 = quantile(v, 0.75);
    s += "<rect x='" + num(a(q1)) + "' y='" + num(cy - 10) + "' width='" +
         num(std::max(1.0, a(q3) - a(q1))) + "' height='20' fill='" + row.colour +
         "' fill-opacity='0.18' stroke='" + row.colour + "'/>";
    s += "<line x1='" + num(a(q2)) + "' y1='" + num(cy - 12) + "' x2='" + num(a(q2)) + "' y2='" +
         num(cy + 12) + "' stroke='" + row.colour + "' stroke-width='2.5'/>";
    for (size_t i = 0; i < v.size(); ++i) {
      s += "<circle cx='" + num(a(v[i])) + "' cy='" + num(cy + 8 * jitter(i)) + "' r='2.2' fill='" +
           row.colour + "' fill-opacity='0.6'/>";
    }
  }
  s += "<line x1='" + num(label_w) + "' y1='" + num(base) + "' x2='" + num(label_w + plot_w) +
       "' y2='" + num(base) + "' stroke='#444'/>";
  s += "<text x='" + num(label_w + plot_w / 2) + "' y='" + num(base + 32) +
       "' text-anchor='middle' font-size='12'>" + html_escape(axis) + "</text>";
  return s + "</svg>";
}

std::string svg_intervals(const std::vector<IntervalRow>& rows,
                          const std::vector<SeriesName>& series, const std::string& axis) {
  const double label_w = 300, plot_w = 480, top = 30;
  const double per_series = 9;
  const double row_h = std::max(22.0, per_series * static_cast<double>(series.size()) + 8);
  const double base = top + row_h * static_cast<double>(rows.size());
  std::string s = svg_open(label_w + plot_w + 30, base + 40);
  s += legend(series, label_w, 16);
  auto x_of = [&](double v) { return label_w + std::clamp(v, 0.0, 1.0) * plot_w; };
  for (int p = 0; p <= 100; p += 25) {
    const double x = x_of(p / 100.0);
    s += "<line x1='" + num(x) + "' y1='" + num(top) + "' x2='" + num(x) + "' y2='" + num(base) +
         "' stroke='#ddd'/>";
    s += "<text x='" + num(x) + "' y='" + num(base + 14) +
         "' text-anchor='middle' font-size='11'>" + std::to_string(p) + "%</text>";
  }
  for (size_t r = 0; r < rows.size(); ++r) {
    const double y0 = top + row_h * static_cast<double>(r);
    if (r % 2 == 1) {
      s += "<rect x='0' y='" + num(y0) + "' width='" + num(label_w + plot_w + 30) + "' height='" +
           num(row_h) + "' fill='#f4f4f4'/>";
    }
    s += "<text x='" + num(label_w - 8) + "' y='" + num(y0 + row_h / 2 + 4) +
         "' text-anchor='end' font-size='12'>" + html_escape(rows[r].label) + "</text>";
    for (const IntervalPoint& pt : rows[r].points) {
      const std::string colour = series.at(static_cast<size_t>(pt.series)).colour;
      const double y = y0 + 8 + per_series * pt.series;
      s += "<line x1='" + num(x_of(pt.low)) + "' y1='" + num(y) + "' x2='" + num(x_of(pt.high)) +
           "' y2='" + num(y) + "' stroke='" + colour + "' stroke-width='2'/>";
      s += "<circle cx='" + num(x_of(pt.value)) + "' cy='" + num(y) + "' r='4' fill='" + colour +
           "'><title>" + html_escape(series[static_cast<size_t>(pt.series)].name) + ": " +
           num(100 * pt.value) + "% (" + num(100 * pt.low) + ".." + num(100 * pt.high) +
           "%)</title></circle>";
    }
  }
  s += "<text x='" + num(label_w + plot_w / 2) + "' y='" + num(base + 32) +
       "' text-anchor='middle' font-size='12'>" + html_escape(axis) + "</text>";
  return s + "</svg>";
}

std::string svg_changes(const std::vector<ChangeRow>& rows, const std::string& axis) {
  const double label_w = 420, plot_w = 420, row_h = 20, top = 10;
  const double base = top + row_h * static_cast<double>(rows.size());
  // Wide enough for every change and, up to twice that, their intervals (wider ones are cut
  // at the edge).
  double values = 1, intervals = 1;
  for (const ChangeRow& r : rows) {
    if (std::isfinite(r.value)) values = std::max(values, std::fabs(r.value));
    for (double v : {r.low, r.high}) {
      if (std::isfinite(v)) intervals = std::max(intervals, std::fabs(v));
    }
  }
  double extent = std::min(intervals, 2 * values);
  // A round extent: 1, 2 or 5 times a power of ten.
  const double decade = std::pow(10.0, std::floor(std::log10(extent)));
  const double step = extent <= decade ? decade : extent <= 2 * decade ? 2 * decade : 5 * decade;
  extent = extent <= step ? step : 10 * decade;
  const auto x_of = [&](double v) {
    return label_w + (std::clamp(v, -extent, extent) + extent) / (2 * extent) * plot_w;
  };
  std::string s = svg_open(label_w + plot_w + 30, base + 40);
  for (int k = -2; k <= 2; ++k) {
    const double v = extent * k / 2, x = x_of(v);
    s += "<line x1='" + num(x) + "' y1='" + num(top) + "' x2='" + num(x) + "' y2='" + num(base) +
         "' stroke='" + (k == 0 ? "#888" : "#ddd") + "'/>";
    s += "<text x='" + num(x) + "' y='" + num(base + 14) +
         "' text-anchor='middle' font-size='11'>" + tick_label(v) + "</text>";
  }
  for (size_t r = 0; r < rows.size(); ++r) {
    const ChangeRow& row = rows[r];
    const double cy = top + row_h * (static_cast<double>(r) + 0.5);
    const char* colour = row.tone > 0 ? "#2ca02c" : row.tone < 0 ? "#d62728" : kBaseColour;
    s += "<text x='" + num(label_w - 8) + "' y='" + num(cy + 4) +
         "' text-anchor='end' font-size='12'>" + html_escape(row.label) + "</text>";
    if (std::isfinite(row.low) && std::isfinite(row.high)) {
      s += "<line x1='" + num(x_of(row.low)) + "' y1='" + num(cy) + "' x2='" + num(x_of(row.high)) +
           "' y2='" + num(cy) + "' stroke='" + colour + "' stroke-width='2'/>";
    }
    s += "<circle cx='" + num(x_of(row.value)) + "' cy='" + num(cy) + "' r='4' fill='" + colour +
         "'><title>" + html_escape(row.label) + ": " + format_number("%+.1f", row.value) + " (" +
         format_number("%+.1f", row.low) + ".." + format_number("%+.1f", row.high) +
         ")</title></circle>";
  }
  s += "<text x='" + num(label_w + plot_w / 2) + "' y='" + num(base + 32) +
       "' text-anchor='middle' font-size='12'>" + html_escape(axis) + "</text>";
  return s + "</svg>";
}

std::string svg_scatter(const std::vector<ScatterPoint>& points,
                        const std::vector<SeriesName>& series, const std::string& x_axis,
                        const std::string& y_axis) {
  const double left = 70, size = 440, top = 34;
  double lo = INFINITY, hi = 0;
  for (const ScatterPoint& p : points) {
    for (double v : {p.x, p.y}) {
      if (v > 0 && std::isfinite(v)) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
    }
  }
  const LogAxis ax = log_axis(lo, hi, left, left + size);
  LogAxis ay = ax;  // same decades; y grows upwards
  ay.x0 = top + size;
  ay.x1 = top;
  std::string s = svg_open(left + size + 30, top + size + 50);
  s += legend(series, left, 16);
  for (double e = ax.lo_exp; e <= ax.hi_exp + 1e-9; e += 1) {
    const double v = std::pow(10.0, e);
    s += "<line x1='" + num(ax(v)) + "' y1='" + num(top) + "' x2='" + num(ax(v)) + "' y2='" +
         num(top + size) + "' stroke='#ddd'/>";
    s += "<line x1='" + num(left) + "' y1='" + num(ay(v)) + "' x2='" + num(left + size) + "' y2='" +
         num(ay(v)) + "' stroke='#ddd'/>";
    s += "<text x='" + num(ax(v)) + "' y='" + num(top + size + 14) +
         "' text-anchor='middle' font-size='11'>" + tick_label(v) + "</text>";
    s += "<text x='" + num(left - 6) + "' y='" + num(ay(v) + 4) +
         "' text-anchor='end' font-size='11'>" + tick_label(v) + "</text>";
  }
  s += "<rect x='" + num(left) + "' y='" + num(top) + "' width='" + num(size) + "' height='" +
       num(size) + "' fill='none' stroke='#444'/>";
  s += "<line x1='" + num(left) + "' y1='" + num(top + size) + "' x2='" + num(left + size) +
       "' y2='" + num(top) + "' stroke='#999' stroke-dasharray='5,4'/>";
  for (const ScatterPoint& p : points) {
    if (!(p.x > 0) || !(p.y > 0)) continue;
    s += "<circle cx='" + num(ax(p.x)) + "' cy='" + num(ay(p.y)) + "' r='3.2' fill='" +
         series.at(static_cast<size_t>(p.series)).colour + "' fill-opacity='0.65'><title>" +
         html_escape(p.title) + "</title></circle>";
  }
  s += "<text x='" + num(left + size / 2) + "' y='" + num(top + size + 34) +
       "' text-anchor='middle' font-size='12'>" + html_escape(x_axis) + "</text>";
  s += "<text transform='translate(16 " + num(top + size / 2) +
       ") rotate(-90)' text-anchor='middle' font-size='12'>" + html_escape(y_axis) + "</text>";
  return s + "</svg>";
}

}  // namespace taskmatrix::harness
