#include "harness/compare/html_report.h"

#include <openssl/evp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "harness/compare/compare_sections.h"
#include "harness/compare/planner_comparison.h"
#include "harness/report/svg_plot.h"
#include "harness/results/json_input.h"
#include "harness/results/trial_schema.h"

namespace taskmatrix::harness {

std::string base64(const std::vector<std::uint8_t>& bytes) {
  std::string out(4 * ((bytes.size() + 2) / 3) + 1, '\0');
  const int n = EVP_EncodeBlock(reinterpret_cast<unsigned char*>(out.data()), bytes.data(),
                                static_cast<int>(bytes.size()));
  out.resize(static_cast<size_t>(n));
  return out;
}

namespace {

const char* const kStyle = R"(<style>
body{font-family:sans-serif;margin:24px auto;max-width:1180px;color:#222;line-height:1.4}
h1{font-size:22px}h2{font-size:18px;margin-top:34px;border-bottom:1px solid #ddd}
table{border-collapse:collapse;font-size:13px;margin:8px 0}
th,td{border:1px solid #ddd;padding:3px 7px;text-align:left;vertical-align:top}
th{background:#f2f2f2}tr.bad td{background:#fde8e8}tr.good td{background:#e8f6e8}
.verdict{padding:10px 14px;font-size:16px;font-weight:bold;border-radius:4px}
.verdict.bad{background:#f8d0d0}.verdict.ok{background:#d6efd6}
.meta{font-size:13px;color:#555}.cards{display:flex;flex-wrap:wrap;gap:14px}
.card{border:1px solid #ccc;border-radius:4px;padding:6px;width:340px;font-size:12px}
.card img{width:100%;display:block}.card .id{font-family:monospace;word-break:break-all}
figure{margin:10px 0}figcaption{font-size:13px;color:#555;margin-bottom:4px}
tr.design td{background:#fdf6dc}.warning{background:#fdf0c4;border:1px solid #e0c060;
padding:8px 12px;border-radius:4px;font-size:14px;white-space:pre-wrap}
.card.wide{width:560px}.shots{display:flex;gap:6px}.shots figure{margin:0;flex:1}
.shots figcaption{font-size:11px}pre.cmd{font-size:11px;background:#f6f6f6;padding:4px;
white-space:pre-wrap;word-break:break-all;margin:4px 0}
</style>)";

std::string fmt(const char* format, double v) { return format_number(format, v); }
std::string p_text(double p) { return html_escape(p_value_text(p)); }
std::string p_phrase(double p) { return html_escape(p_value_phrase(p)); }

std::string td(const std::string& s) { return "<td>" + s + "</td>"; }

std::string work_total(const PairedGroup& g, const std::string& field) {
  for (const WorkCountChange& w : g.work) {
    if (w.field != field) continue;
    std::string cell = fmt("%.0f", w.base_total) + " &rarr; " + fmt("%.0f", w.new_total);
    if (w.changed_trials > 0) cell += " (" + std::to_string(w.changed_trials) + " changed)";
    return cell;
  }
  return "-";
}

std::string verdict_text(const PairedGroup& g, const CompareThresholds& t) {
  std::string v;
  for (const std::string& r : g.regressions) v += "<b>regression</b>: " + html_escape(r) + "<br>";
  for (const std::string& r : g.by_design) {
    v += std::string("<i>") + kByDesign + "</i>: " + html_escape(r) + "<br>";
  }
  for (const std::string& r : g.improvements) v += "better: " + html_escape(r) + "<br>";
  return v.empty() ? html_escape(no_change_text(g, t)) : v;
}

std::string row_class(const PairedGroup& g) {
  if (!g.regressions.empty()) return " class='bad'";
  if (!g.by_design.empty()) return " class='design'";
  if (!g.improvements.empty()) return " class='good'";
  return "";
}

std::string success_text(int s, int n, const Interval& ci) {
  return std::to_string(s) + "/" + std::to_string(n) + " (" + fmt("%.0f", 100 * ci.low) +
         "&ndash;" + fmt("%.0f", 100 * ci.high) + "%)";
}

std::string time_text(const PairedGroup& g) {
  if (g.time_pairs == 0) return "-";
  return "&times;" + fmt("%.2f", g.time_ratio) + " (" + fmt("%.2f", g.time_ratio_low) + "&ndash;" +
         fmt("%.2f", g.time_ratio_high) + ", " + std::to_string(g.time_pairs) + " pairs)";
}

std::string overall_table(const Comparison& c, const std::string& base_name,
                          const std::string& new_name) {
  const PairedGroup& o = c.overall;
  std::string s = "<table><tr><th></th><th>" + html_escape(base_name) + "</th><th>" +
                  html_escape(new_name) + "</th><th>change</th></tr>";
  s += "<tr><td>success</td>" + td(success_text(o.base_successes, o.pairs, o.base_ci)) +
       td(success_text(o.new_successes, o.pairs, o.new_ci)) +
       td(std::to_string(o.only_base_success) + " now fail, " + std::to_string(o.only_new_success) +
          " now succeed; McNemar p " + p_phrase(o.mcnemar_p)) +
       "</tr>";
  if (o.time_pairs > 0) {
    s += "<tr><td>planning time per trial (median s)</td>" +
         td(fmt("%.4f", quantile(o.base_planning_s, 0.5))) +
         td(fmt("%.4f", quantile(o.new_planning_s, 0.5))) +
         td(time_text(o) + "; Wilcoxon p " + p_phrase(o.wilcoxon_p)) + "</tr>";
  }
  for (const WorkCountChange& w : o.work) {
    s += "<tr><td>" + w.field + " (total)</td>" + td(fmt("%.0f", w.base_total)) +
         td(fmt("%.0f", w.new_total)) +
         td((w.base_total > 0 ? "&times;" + fmt("%.3f", w.new_total / w.base_total) + "; " : "") +
            trials_changed(w.changed_trials)) +
         "</tr>";
  }
  return s + "</table><p>Overall: " + verdict_text(o, c.thresholds) + "</p>";
}

std::string group_table(const Comparison& c) {
  std::string s =
      "<table><tr><th>scenario</th><th>robot</th><th>environment</th><th>planner</th>"
      "<th>success</th><th>McNemar p</th><th>planning time ratio (95% CI)</th>"
      "<th>Wilcoxon p</th>";
  // The work counts the table shows per group (FieldDisplay::compare_groups).
  for (const TrialField& f : kTrialFields) {
    if (f.display.compare_groups) s += "<th>" + html_escape(std::string(f.display.label)) + "</th>";
  }
  s += "<th>verdict</th></tr>";
  for (const PairedGroup& g : c.groups) {
    const std::string planner =
        g.base_planner == g.new_planner ? g.base_planner : g.base_planner + " → " + g.new_planner;
    s += "<tr" + row_class(g) + ">" + td(html_escape(g.scenario)) + td(html_escape(g.robot)) +
         td(html_escape(g.environment)) + td(html_escape(planner)) +
         td(std::to_string(g.base_successes) + "/" + std::to_string(g.pairs) + " &rarr; " +
            std::to_string(g.new_successes) + "/" + std::to_string(g.pairs)) +
         td(p_text(g.mcnemar_p)) + td(time_text(g)) + td(p_text(g.wilcoxon_p));
    for (const TrialField& f : kTrialFields) {
      if (f.display.compare_groups) s += td(work_total(g, std::string(f.name)));
    }
    s += td(verdict_text(g, c.thresholds)) + "</tr>";
  }
  return s + "</table>";
}

std::vector<double> planning_times(const std::vector<nlohmann::json>& trials,
                                   const std::string& planner) {
  std::vector<double> out;
  for (const nlohmann::json& t : trials) {
    if (t.value("planner", std::string()) != planner) continue;
    const auto it = t.find(kPlanningTimeField);
    if (it != t.end() && it->is_number() && it->get<double>() > 0) out.push_back(it->get<double>());
  }
  return out;
}

std::set<std::string> planners_of(const std::vector<nlohmann::json>& trials) {
  std::set<std::string> out;
  for (const nlohmann::json& t : trials) out.insert(t.value("planner", std::string()));
  return out;
}

std::string group_label(const PairedGroup& g) {
  return g.scenario + " · " + g.robot + " · " + g.environment;
}

std::string provenance_line(const nlohmann::json& p) {
  if (!p.is_object()) return "no provenance.json";
  std::string s;
  auto add = [&](const std::string& label, const nlohmann::json* v) {
    if (v == nullptr || v->is_null()) return;
    s += (s.empty() ? "" : "; ") + label + " " +
         html_escape(valid_utf8(v->is_string() ? v->get<std::string>() : json_text(*v)));
  };
  auto field = [&](const char* key) { return p.contains(key) ? &p[key] : nullptr; };
  add("built from commit", field("git_commit"));
  add("with local changes", field("git_dirty"));
  if (p.contains("root") && p["root"].is_object()) {
    const nlohmann::json& r = p["root"];
    add("models from", r.contains("path") ? &r["path"] : nullptr);
    if (r.contains("git_commit") && r["git_commit"].is_null()) {
      s += " (not a git checkout)";
    } else {
      add("at commit", r.contains("git_commit") ? &r["git_commit"] : nullptr);
    }
  }
  if (p.contains("model_files") && p["model_files"].is_array()) {
    s += "; " + std::to_string(p["model_files"].size()) + " model files hashed";
  }
  add("OMPL", field("ompl_version"));
  add("MuJoCo", field("mujoco_version"));
  add("started", field("started_at"));
  if (p.contains("host") && p["host"].is_object() && p["host"].contains("cpu")) {
    add("CPU", &p["host"]["cpu"]);
  }
  return s;
}

// Rows of planning-time distributions: one per planner and run that has trials.
void add_distribution_rows(std::vector<DistributionRow>& rows,
                           const std::vector<nlohmann::json>& trials, const std::string& label,
                           const std::string& colour) {
  for (const std::string& p : planners_of(trials)) {
    std::vector<double> times = planning_times(trials, p);
    if (times.empty()) continue;
    rows.push_back({p + " · " + label, colour, std::move(times)});
  }
}

// Path quality, power, failures by group and changed trials: the sections both reports share.
std::string detail_sections(const Comparison& c, const std::string& level) {
  const std::string h2 = "<" + level + ">", h2_end = "</" + level + ">";
  std::string h;
  if (!c.flips.empty()) {
    h += h2 + "Trials whose outcome changed" + h2_end + html_table(flips_table(c));
  }
  const ReportTable failures = failures_table(c);
  if (!failures.rows.empty()) {
    h += h2 + "Failures by group" + h2_end +
         "<p class='meta'>Where each failed trial failed (its programs, outermost first) and "
         "why.</p>" +
         html_table(failures);
  }
  h += h2 + "Path quality" + h2_end + "<p class='meta'>" + html_escape(path_quality_method(c)) +
       "</p>";
  std::vector<ChangeRow> changes;
  const auto add_changes = [&](const std::string& name, const PairedGroup& g, bool all) {
    for (const PathQualityChange& q : g.path_quality) {
      if (q.pairs < 2 || !std::isfinite(q.percent()) || (!all && !q.significant())) continue;
      const double scale = 100 / q.base_mean;
      changes.push_back({name + ": " + q.name, q.mean_change * scale, q.change_low * scale,
                         q.change_high * scale, q.significant() ? (q.better() ? 1 : -1) : 0});
    }
  };
  add_changes("all pairs", c.overall, true);
  for (const PairedGroup& g : c.groups) add_changes(group_name(g), g, false);
  if (!changes.empty()) {
    h += "<figure><figcaption>Mean paired change new - base in % of the base mean, with 95% "
         "intervals: every measure over all pairs, then each group's significant ones (green: "
         "better, red: worse).</figcaption>" +
         svg_changes(changes, "change new - base (% of base mean)") + "</figure>";
  }
  h += html_table(path_quality_table(c));
  h += h2 + "Statistical power" + h2_end + "<p class='meta'>" + html_escape(power_method(c)) +
       "</p>" + html_table(power_table(c));
  return h;
}

std::string shell_block(const std::vector<std::string>& commands) {
  std::string h;
  for (const std::string& cmd : commands) h += "<pre class='cmd'>" + html_escape(cmd) + "</pre>";
  return h;
}

}  // namespace

std::string compare_html(const Comparison& c, const std::vector<nlohmann::json>& base,
                         const std::vector<nlohmann::json>& fresh,
                         const nlohmann::json& base_provenance,
                         const nlohmann::json& new_provenance,
                         const std::vector<TrialSnapshot>& snapshots, int snapshots_left_out,
                         const ProvenanceDiff* differences) {
  const CompareThresholds& t = c.thresholds;
  std::string h = "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>Compare " +
                  html_escape(c.base_label) + " → " + html_escape(c.new_label) + "</title>" +
                  kStyle + "</head><body>";
  h += "<h1>Compare <code>" + html_escape(c.base_label) + "</code> → <code>" +
       html_escape(c.new_label) + "</code></h1>";
  h += "<p class='meta'>base: " + provenance_line(base_provenance) +
       "<br>new: " + provenance_line(new_provenance) + "</p>";
  h += c.regression() ? "<p class='verdict bad'>Regression</p>"
                      : "<p class='verdict ok'>No regression</p>";
  if (differences != nullptr) {
    const std::string warning = provenance_warning(*differences);
    if (!warning.empty()) h += "<div class='warning'>" + html_escape(warning) + "</div>";
  }
  h += "<p class='meta'>" + std::to_string(c.overall.pairs) + " trials paired by id";
  if (!c.only_in_base.empty() || !c.only_in_new.empty()) {
    h += " (" + std::to_string(c.only_in_base.size()) + " only in the base, " +
         std::to_string(c.only_in_new.size()) + " only in the new run: left out)";
  }
  h += ". A regression is a success drop of at least " + fmt("%.0f", 100 * t.max_success_drop) +
       " points with McNemar p &lt; " + fmt("%.2f", t.alpha) +
       ", a planning-time ratio whose 95% bootstrap interval lies above &times;" +
       fmt("%.2f", t.max_time_ratio) + " with Wilcoxon p &lt; " + fmt("%.2f", t.alpha) +
       " (at least " + std::to_string(t.min_time_pairs) +
       " pairs that both planned), or total collision checks above &times;" +
       fmt("%.2f", t.max_work_ratio) +
       (t.max_new_failures >= 0
            ? ", or more than " + std::to_string(t.max_new_failures) + " trials that now fail"
            : std::string()) +
       ".</p>";
  h += "<h2>Overall</h2>" + overall_table(c, "base", "new");

  h += "<h2>Planning time per trial, by planner</h2><figure><figcaption>Every trial that "
       "planned; box: quartiles and median.</figcaption>";
  std::vector<DistributionRow> rows;
  add_distribution_rows(rows, base, "base", kBaseColour);
  add_distribution_rows(rows, fresh, "new", series_colour(0));
  h += svg_distributions(rows, "planning time per trial (s, log scale)") + "</figure>";

  h += "<h2>Success rate by group</h2><figure><figcaption>Wilson 95% intervals.</figcaption>";
  std::vector<IntervalRow> irows;
  for (const PairedGroup& g : c.groups) {
    irows.push_back(
        {group_label(g) + (g.base_planner == g.new_planner ? " · " + g.new_planner : ""),
         {{0, g.pairs ? static_cast<double>(g.base_successes) / g.pairs : 0, g.base_ci.low,
           g.base_ci.high},
          {1, g.pairs ? static_cast<double>(g.new_successes) / g.pairs : 0, g.new_ci.low,
           g.new_ci.high}}});
  }
  h += svg_intervals(irows, {{"base", kBaseColour}, {"new", series_colour(0)}}, "success rate") +
       "</figure>";

  h += "<h2>Planning time, trial by trial</h2><figure><figcaption>Each point is one trial id: "
       "base (x) against new (y). Below the diagonal the new run planned faster.</figcaption>";
  std::vector<ScatterPoint> points;
  std::vector<SeriesName> robots;
  std::map<std::string, int> robot_index;
  for (const PairedGroup& g : c.groups) {
    if (!robot_index.count(g.robot)) {
      robot_index[g.robot] = static_cast<int>(robots.size());
      robots.push_back({g.robot, series_colour(static_cast<int>(robots.size()))});
    }
    for (size_t i = 0; i < g.base_planning_s.size(); ++i) {
      points.push_back({g.base_planning_s[i], g.new_planning_s[i], robot_index[g.robot],
                        g.time_pair_ids[i] + ": " + fmt("%.4f", g.base_planning_s[i]) + " s → " +
                            fmt("%.4f", g.new_planning_s[i]) + " s"});
    }
  }
  h += svg_scatter(points, robots, "base planning time (s)", "new planning time (s)") + "</figure>";

  h += "<h2>Per group</h2>" + group_table(c);
  h += detail_sections(c, "h2");
  h += "<h2>Failed trials</h2>";
  if (snapshots.empty() && snapshots_left_out == 0) h += "<p>No trial failed.</p>";
  if (!snapshots.empty()) {
    h += "<p class='meta'>Each failed trial at the moment it failed: the overview camera and a "
         "close-up aimed at the moving hand or the object it holds. The commands render the "
         "whole trial as video from its recording (overview, then the close-up).</p>";
  }
  h += "<div class='cards'>";
  for (const TrialSnapshot& s : snapshots) {
    h += "<div class='card wide'>";
    if (!s.png.empty()) {
      const std::string at = s.time_s >= 0 ? " at t = " + fmt("%.2f", s.time_s) + " s" : "";
      h += "<div class='shots'><figure><img alt='overview of " + html_escape(s.trial_id) + at +
           "' src='data:image/png;base64," + base64(s.png) + "'><figcaption>overview" +
           html_escape(at) + "</figcaption></figure>";
      if (!s.close_up.empty()) {
        h += "<figure><img alt='close-up of " + html_escape(s.trial_id) +
             "' src='data:image/png;base64," + base64(s.close_up) +
             "'><figcaption>close-up: " + html_escape(s.focus) + "</figcaption></figure>";
      }
      h += "</div>";
    }
    h += "<div class='id'>" + html_escape(s.trial_id) + "</div><div>" + html_escape(s.run) +
         " run: <b>" + html_escape(s.status) + "</b>" +
         (s.where.empty() ? "" : " in <code>" + html_escape(s.where) + "</code>") + ": " +
         html_escape(s.reason) + "</div>";
    if (!s.note.empty()) h += "<div class='meta'>" + html_escape(s.note) + "</div>";
    h += shell_block(s.commands);
    h += "</div>";
  }
  h += "</div>";
  if (snapshots_left_out > 0) {
    h += "<p class='meta'>" + std::to_string(snapshots_left_out) +
         " more failed trials not pictured (--max-snapshots).</p>";
  }
  if (differences != nullptr) {
    const ReportTable table = provenance_diff_table(*differences);
    h += "<h2>What ran</h2><p class='meta'>base: " + provenance_line(base_provenance) +
         "<br>new: " + provenance_line(new_provenance) + "</p>" +
         (table.rows.empty() ? "<p>The same build loaded the same model and scenario files.</p>"
                             : html_table(table));
  }
  if (!c.only_in_base.empty() || !c.only_in_new.empty()) {
    h += "<h2>Unpaired trials</h2><ul>";
    for (const std::string& id : c.only_in_base) {
      h += "<li>only in the base: <code>" + html_escape(id) + "</code></li>";
    }
    for (const std::string& id : c.only_in_new) {
      h += "<li>only in the new run: <code>" + html_escape(id) + "</code></li>";
    }
    h += "</ul>";
  }
  return h + "</body></html>\n";
}

std::string planners_html(const std::string& run_name, const std::vector<nlohmann::json>& trials,
                          const std::vector<std::string>& planners,
                          const std::vector<Comparison>& vs_reference,
                          std::span<const TrialField> fields) {
  std::string h = "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>Planners of " +
                  html_escape(run_name) + "</title>" + kStyle + "</head><body>";
  h += "<h1>Planners of run <code>" + html_escape(run_name) + "</code></h1>";
  h += "<p class='meta'>The same trials (scenarios, robots, environments, layouts and seeds) "
       "under each planner; each planner is compared with the first, <b>" +
       html_escape(planners.empty() ? "" : planners[0]) + "</b>, pair by pair.</p>";

  h += "<h2>Summary</h2><table><tr><th>planner</th><th>trials</th><th>success (95% CI)</th>"
       "<th>planning time per trial s (median / p90)</th>";
  for (const std::string& heading : planner_measure_headings(fields)) {
    h += "<th>" + html_escape(heading) + "</th>";
  }
  h += "</tr>";
  std::vector<SeriesName> series;
  for (size_t i = 0; i < planners.size(); ++i) {
    series.push_back({planners[i], series_colour(static_cast<int>(i))});
    int n = 0, s = 0;
    for (const nlohmann::json& t : trials) {
      if (t.value("planner", std::string()) != planners[i]) continue;
      ++n;
      s += t.value("success", false);
    }
    const std::vector<double> times = planning_times(trials, planners[i]);
    h += "<tr>" + td(html_escape(planners[i])) + td(std::to_string(n)) +
         td(success_text(s, n, wilson_interval(s, n))) +
         td(fmt("%.4f", quantile(times, 0.5)) + " / " + fmt("%.4f", quantile(times, 0.9)));
    for (const std::string& cell : planner_measure_cells(trials, planners[i], fields)) {
      h += td(html_escape(cell));
    }
    h += "</tr>";
  }
  h += "</table>";

  h += "<h2>Planning time per trial</h2><figure><figcaption>Every trial that planned; box: "
       "quartiles and median.</figcaption>";
  std::vector<DistributionRow> rows;
  for (size_t i = 0; i < planners.size(); ++i) {
    rows.push_back({planners[i], series[i].colour, planning_times(trials, planners[i])});
  }
  h += svg_distributions(rows, "planning time per trial (s, log scale)") + "</figure>";

  if (!vs_reference.empty()) {
    h += "<h2>Success rate by group</h2><figure><figcaption>Wilson 95% intervals.</figcaption>";
    std::vector<IntervalRow> irows;
    for (size_t gi = 0; gi < vs_reference[0].groups.size(); ++gi) {
      const PairedGroup& ref = vs_reference[0].groups[gi];
      IntervalRow row{group_label(ref), {}};
      row.points.push_back({0, ref.pairs ? static_cast<double>(ref.base_successes) / ref.pairs : 0,
                            ref.base_ci.low, ref.base_ci.high});
      for (size_t k = 0; k < vs_reference.size(); ++k) {
        const int series_index = static_cast<int>(
            std::find(planners.begin(), planners.end(), vs_reference[k].new_label) -
            planners.begin());
        for (const PairedGroup& g : vs_reference[k].groups) {
          if (group_label(g) != row.label) continue;
          row.points.push_back({series_index,
                                g.pairs ? static_cast<double>(g.new_successes) / g.pairs : 0,
                                g.new_ci.low, g.new_ci.high});
        }
      }
      irows.push_back(std::move(row));
    }
    h += svg_intervals(irows, series, "success rate") + "</figure>";

    h += "<h2>Planning time, trial by trial</h2><figure><figcaption>Each point is one trial: "
         "the reference planner's time (x) against another planner's (y).</figcaption>";
    std::vector<ScatterPoint> points;
    std::vector<SeriesName> others;  // in the order of vs_reference, coloured as in `series`
    for (size_t k = 0; k < vs_reference.size(); ++k) {
      const auto at = std::find(planners.begin(), planners.end(), vs_reference[k].new_label);
      others.push_back(
          {vs_reference[k].new_label, series_colour(static_cast<int>(at - planners.begin()))});
      for (const PairedGroup& g : vs_reference[k].groups) {
        for (size_t i = 0; i < g.base_planning_s.size(); ++i) {
          points.push_back(
              {g.base_planning_s[i], g.new_planning_s[i], static_cast<int>(k), g.time_pair_ids[i]});
        }
      }
    }
    h += svg_scatter(points, others,
                     (planners.empty() ? std::string() : planners[0]) + " planning time (s)",
                     "other planner's planning time (s)") +
         "</figure>";
  }
  for (const Comparison& c : vs_reference) {
    h += "<h2>" + html_escape(c.new_label) + " against " + html_escape(c.base_label) + "</h2>";
    h += overall_table(c, c.base_label, c.new_label) + group_table(c);
    h += detail_sections(c, "h3");
  }
  return h + "</body></html>\n";
}

}  // namespace taskmatrix::harness
