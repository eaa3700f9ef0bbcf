#include "harness/run/scenes_job.h"

#include <chrono>
#include <cstdio>
#include <string>

#include "harness/backends/backends.h"
#include "taskmatrix/core/motion_planning.h"
#include "taskmatrix/mujoco/mujoco_backend.h"
#include "taskmatrix/mujoco/offscreen_renderer.h"
#include "taskmatrix/mujoco/scene.h"

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
  using mujoco::CameraView;
  int scenes_with_contacts = 0, images = 0;
  const auto job_start = std::chrono::steady_clock::now();
  out << "| robot | environment | seed | obstacles | load ms | layout us | robot contacts | images "
         "|\n"
      << "|---|---|---|---|---|---|---|---|\n";
  for (const std::string& robot : catalog.robots()) {
    for (const std::string& env : catalog.environments()) {
      const auto t_load = std::chrono::steady_clock::now();
      // Pictures are the MuJoCo backend's (its offscreen renderer).
      const std::shared_ptr<const mujoco::Scene> scene =
          mujoco::scene_of(*backend().load(catalog.robot_dir(robot), catalog.environment_dir(env)));
      const double load_ms = core::seconds_since(t_load) * 1e3;
      mujoco::WorkerScene worker(scene);
      mujoco::OffscreenRenderer renderer(scene->model(), options.width, options.height);
      CameraView overview;
      if (!scene->environment().cameras.empty()) {
        overview.fixed_camera =
            mj_name2id(scene->model(), mjOBJ_CAMERA, scene->environment().cameras.front().c_str());
      }
      CameraView head;
      head.fixed_camera = scene->head_camera();
      for (int seed = 1; seed <= options.seeds; ++seed) {
        const auto t_layout = std::chrono::steady_clock::now();
        const core::ObstacleLayout layout = scene->make_layout(options.obstacles, seed);
        worker.apply_layout(layout);
        worker.reset_to_start();
        const double layout_us = core::seconds_since(t_layout) * 1e6;
        const auto contacts = worker.robot_contacts();
        if (!contacts.empty()) ++scenes_with_contacts;

        const std::string stem = robot + "_" + env + "_seed" + std::to_string(seed);
        const auto scene_png = options.out / (stem + ".png");
        const auto head_png = options.out / (stem + "_head.png");
        mujoco::write_png(scene_png, renderer.render_rgb(worker.model(), worker.data(), overview));
        mujoco::write_png(head_png, renderer.render_rgb(worker.model(), worker.data(), head));
        images += 2;
        std::string contact_text = std::to_string(contacts.size());
        if (!contacts.empty())
          contact_text += " (" + contacts[0].body1 + "~" + contacts[0].body2 + ")";
        out << "| " << robot << " | " << env << " | " << seed << " | " << layout.obstacles.size()
            << " | " << (seed == 1 ? fixed(load_ms, 1) : std::string("")) << " | "
            << fixed(layout_us, 0) << " | " << contact_text << " | " << scene_png.string() << ", "
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
