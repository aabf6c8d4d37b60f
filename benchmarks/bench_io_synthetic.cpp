// Speed of the foundation: generating synthetic buildings and robot maps of growing size, and
// loading real maps. Run: build/benchmarks/areamatch_bench --benchmark_filter=^BM_ --benchmark_out=io.json
#include <areamatch/areamatch.hpp>
#include <areamatch/synthetic.hpp>
#include <areamatch/io.hpp>

#include <benchmark/benchmark.h>

#include <sys/stat.h>

namespace areamatch_bench::io_synthetic {

areamatch::BuildingParams square(double side) {
  areamatch::BuildingParams p;
  p.width_m = side;
  p.height_m = side;
  return p;
}

void BM_GenerateBuilding(benchmark::State& state) {
  const auto params = square(static_cast<double>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(areamatch::generate_building(params, 1));
  state.SetLabel(std::to_string(state.range(0)) + " m square");
}
BENCHMARK(BM_GenerateBuilding)->Arg(10)->Arg(50)->Arg(100)->Arg(200)->Unit(benchmark::kMillisecond);

void BM_MakeRobotMap(benchmark::State& state) {
  const auto building = areamatch::generate_building(square(static_cast<double>(state.range(0))), 1);
  areamatch::RobotMapParams rp;
  rp.rotation_rad = 0.6;
  rp.wall_noise_m = 0.03;
  rp.max_clutter_per_room = 3;
  for (auto _ : state) benchmark::DoNotOptimize(areamatch::make_robot_map(building, rp, 1));
}
BENCHMARK(BM_MakeRobotMap)->Arg(10)->Arg(50)->Unit(benchmark::kMillisecond);

void BM_PngRoundTrip(benchmark::State& state) {
  const auto building = areamatch::generate_building(square(50.0), 1);
  const auto image = areamatch::image_from_grid(building.layout);
  for (auto _ : state) benchmark::DoNotOptimize(areamatch::decode_png(areamatch::encode_png(image), "bench"));
}
BENCHMARK(BM_PngRoundTrip)->Unit(benchmark::kMillisecond);

void BM_LoadSharedMap(benchmark::State& state) {
  const std::string path = std::string(AREAMATCH_SHARED_DIR) + "/maps/office_g.yaml";
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    state.SkipWithError("shared maps not present");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(areamatch::load_map(path));
}
BENCHMARK(BM_LoadSharedMap)->Unit(benchmark::kMillisecond);

}  // namespace areamatch_bench::io_synthetic
