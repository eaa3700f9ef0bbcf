// Scene set-up costs against raw MuJoCo, measured in the same run:
//   BM_LoadXML_Raw        mj_loadXML of the composed scene (the floor for any loader)
//   BM_SceneLoad          Scene::load: YAML, standalone checks of both files, compose, compile,
//                         name validation (once per process and scene)
//   BM_CopyModel_Raw      mj_copyModel + mj_makeData (once per worker)
//   BM_NewLayout          generate_layout + apply_layout + reset_to_start (once per trial)
// Per-trial layout changes must cost far less than recompiling XML (BM_LoadXML_Raw).
#include <benchmark/benchmark.h>

#include <cstring>

#include "harness/scenario/model_catalog.h"
#include "taskmatrix/mujoco/scene.h"

namespace {

using namespace taskmatrix;

const harness::ModelCatalog& catalog() {
  static const harness::ModelCatalog c(TASKMATRIX_BENCH_ROOT);
  return c;
}

std::shared_ptr<const mujoco::Scene> tall_in_kitchen() {
  static auto scene =
      mujoco::Scene::load(catalog().robot_dir("tallbot"), catalog().environment_dir("kitchen"));
  return scene;
}

void BM_LoadXML_Raw(benchmark::State& state) {
  const std::string& xml = tall_in_kitchen()->composed_mjcf();
  for (auto _ : state) {
    mujoco::ModelPtr m = mujoco::compile_mjcf_text(xml, "bench");
    benchmark::DoNotOptimize(m.get());
  }
}
BENCHMARK(BM_LoadXML_Raw)->Unit(benchmark::kMillisecond);

void BM_SceneLoad(benchmark::State& state) {
  for (auto _ : state) {
    auto scene =
        mujoco::Scene::load(catalog().robot_dir("tallbot"), catalog().environment_dir("kitchen"));
    benchmark::DoNotOptimize(scene.get());
  }
}
BENCHMARK(BM_SceneLoad)->Unit(benchmark::kMillisecond);

void BM_CopyModel_Raw(benchmark::State& state) {
  const mjModel* m = tall_in_kitchen()->model();
  for (auto _ : state) {
    mujoco::ModelPtr copy = mujoco::copy_model(m);
    mujoco::DataPtr d = mujoco::make_data(copy.get());
    benchmark::DoNotOptimize(d.get());
  }
}
BENCHMARK(BM_CopyModel_Raw)->Unit(benchmark::kMicrosecond);

void BM_NewLayout(benchmark::State& state) {
  auto scene = tall_in_kitchen();
  mujoco::WorkerScene worker(scene);
  const core::LayoutRequest request = scene->layout_request(static_cast<int>(state.range(0)));
  std::uint64_t seed = 0;
  for (auto _ : state) {
    worker.apply_layout(core::generate_layout(request, ++seed));
    worker.reset_to_start();
    benchmark::DoNotOptimize(worker.data()->ncon);
  }
}
BENCHMARK(BM_NewLayout)->Arg(10)->Arg(20)->Unit(benchmark::kMicrosecond);

}  // namespace
