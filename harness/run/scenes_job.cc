#include "harness/run/scenes_job.h"

#include <chrono>
#include <cstdio>
#include <string>

#include "harness/backends/backends.h"
#include "taskmatrix/core/motion_planning.h"
#include "taskmatrix/io/png.h"

namespace taskmatrix::harness {

namespace {

std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

}  // namespace

int run_scenes_job(const ModelCatalog& catalog, const ScenesJobOptions& options,
                   std::ostream& out) {
  int scenes_with_contacts = 0, images = 0;
  const auto job_start = std::chrono::steady_clock::now();
  out << "| robot | environment | seed | obstacles | load ms | layout us | robot contacts | images "
         "|\n"
      << "|---|---|---|---|---|---|---|---|\n";
  for (const std::string& robot : catalog.robots()) {
    for (const std::string& env : catalog.environments()) {
      const auto t_load = std::chrono::steady_clock::now();
      const std::shared_ptr<const core::LoadedScene> scene =
          backend().load(catalog.robot_dir(robot), catalog.environment_dir(env));
      const double load_ms = core::seconds_since(t_load) * 1e3;
      core::Camera overview;  // the environment's first camera, else the free camera
      core::Camera head;
      head.name = "head";
      if (!scene->environment().cameras.empty()) {
        overview.name = scene->environment().cameras.front();
      }
      for (int seed = 1; seed <= options.seeds; ++seed) {
        const auto t_layout = std::chrono::steady_clock::now();
        core::ObstacleOptions obstacles;
        obstacles.count = options.obstacles;
        const core::TrialLayout layout =
            scene->make_trial_layout(obstacles, {}, static_cast<std::uint64_t>(seed));
        const double layout_us = core::seconds_since(t_layout) * 1e6;
        std::vector<core::StartContact> contacts;
        for (core::StartContact& c : scene->start_contacts(layout)) {
          if (c.robot) contacts.push_back(std::move(c));
        }
        if (!contacts.empty()) ++scenes_with_contacts;

        const std::unique_ptr<core::SceneView> view = scene->make_view(layout);
        const std::string stem = robot + "_" + env + "_seed" + std::to_string(seed);
        const auto scene_png = options.out / (stem + ".png");
        const auto head_png = options.out / (stem + "_head.png");
        io::write_png(scene_png, view->render(overview, options.width, options.height));
        io::write_png(head_png, view->render(head, options.width, options.height));
        images += 2;
        std::string contact_text = std::to_string(contacts.size());
        if (!contacts.empty())
          contact_text += " (" + contacts[0].first + "~" + contacts[0].second + ")";
        out << "| " << robot << " | " << env << " | " << seed << " | "
            << layout.obstacles.obstacles.size() << " | "
            << (seed == 1 ? fixed(load_ms, 1) : std::string("")) << " | " << fixed(layout_us, 0)
            << " | " << contact_text << " | " << scene_png.string() << ", "
            << head_png.filename().string() << " |\n";
      }
    }
  }
  out << "\n"
      << images << " images in " << options.out.string() << ", "
      << fixed(core::seconds_since(job_start), 1)
      << " s; scenes with robot contacts at rest: " << scenes_with_contacts << "\n";
  return scenes_with_contacts;
}

}  // namespace taskmatrix::harness
