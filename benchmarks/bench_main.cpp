// areamatch_bench: every benchmark in one program (one compile of the library instead of four),
// grouped by name prefix; select with --benchmark_filter, e.g. '^pair/' or '^segment/'.
#include "bench_support.hpp"

#include <benchmark/benchmark.h>

int main(int argc, char** argv) {
  areamatch_bench::register_segmentation();
  areamatch_bench::register_matching();
  areamatch_bench::register_merge();
  areamatch_bench::register_assessing();
  areamatch_bench::register_growth();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
