// Perception costs against raw MuJoCo, measured in the same run (tallbot in the kitchen,
// 8 obstacles, the head looking at the table):
//   BM_RayGrid_Raw        64 x 48 mj_ray calls from the head camera, nothing else (the floor)
//   BM_HeadSensor         HeadSensor::capture + recognise at 64 x 48 (geom labelling,
//                         depth, visibility shares)
//   BM_GroundTruth        GroundTruthPerception::update (boxes of every object)
// The sensor runs at the perception rate (10 Hz by default), not the control rate.
#include <benchmark/benchmark.h>

#include <cmath>

#include "harness/scenario/model_catalog.h"
#include "taskmatrix/mujoco/head_sensor.h"

namespace {

using namespace taskmatrix;

std::unique_ptr<mujoco::MujocoSkillset> skills() {
  static const harness::ModelCatalog catalog(TASKMATRIX_BENCH_ROOT);
  static auto scene =
      mujoco::Scene::load(catalog.robot_dir("tallbot"), catalog.environment_dir("kitchen"));
  auto s = std::make_unique<mujoco::MujocoSkillset>(scene);
  s->apply_layout(scene->make_layout(8, 1));
  return s;
}

void BM_RayGrid_Raw(benchmark::State& state) {
  auto s = skills();
  const mjModel* m = s->model();
  const mjData* d = s->sim_data();
  const int cam = s->scene().head_camera();
  const double* R = d->cam_xmat + 9 * cam;
  const double tan_half = std::tan(m->cam_fovy[cam] * M_PI / 360.0);
  const mjtByte groups[mjNGROUP] = {1, 1, 1, 0, 0, 0};
  for (auto _ : state) {
    int hits = 0;
    for (int r = 0; r < 48; ++r) {
      for (int c = 0; c < 64; ++c) {
        const double u = (2.0 * (c + 0.5) / 64 - 1.0) * tan_half * 64 / 48;
        const double v = (1.0 - 2.0 * (r + 0.5) / 48) * tan_half;
        double dir[3];
        for (int i = 0; i < 3; ++i) dir[i] = u * R[3 * i] + v * R[3 * i + 1] - R[3 * i + 2];
        mju_normalize3(dir);
        int geom = -1;
        hits += mj_ray(m, d, d->cam_xpos + 3 * cam, dir, groups, 1, m->cam_bodyid[cam], &geom) > 0;
      }
    }
    benchmark::DoNotOptimize(hits);
  }
}
BENCHMARK(BM_RayGrid_Raw)->Unit(benchmark::kMillisecond);

void BM_HeadSensor(benchmark::State& state) {
  auto s = skills();
  mujoco::HeadSensor sensor(*s, {64, 48, 5.0, 3});
  for (auto _ : state) {
    sensor.capture();
    benchmark::DoNotOptimize(sensor.recognise());
  }
}
BENCHMARK(BM_HeadSensor)->Unit(benchmark::kMillisecond);

void BM_GroundTruth(benchmark::State& state) {
  auto s = skills();
  mujoco::GroundTruthPerception perception(*s);
  core::PerceptualModel model;
  for (auto _ : state) {
    perception.update(0.0, model);
    benchmark::DoNotOptimize(model.objects().size());
  }
}
BENCHMARK(BM_GroundTruth)->Unit(benchmark::kMicrosecond);

}  // namespace
