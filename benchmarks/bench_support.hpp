#pragma once
// Shared by the benchmark groups of areamatch_bench: each group's registration function (called
// by bench_main.cpp before Google Benchmark reads its flags) and a value built on first use, so
// that a --benchmark_filter run pays only for the inputs of what it selects.
#include <functional>
#include <memory>
#include <optional>
#include <utility>

namespace areamatch_bench {

void register_segmentation();  // bench_segmentation.cpp: segment/, voronoi/, voronoi_boost/
void register_matching();      // bench_matching.cpp: match/, pair/, onto_prepared/
void register_merge();         // bench_merge.cpp: merge/
void register_assessing();     // bench_assess.cpp: warp/, assess/
void register_growth();        // bench_growth.cpp: growth/pair/, growth/onto_prepared/
// bench_io_synthetic.cpp registers its BM_ benchmarks statically (BENCHMARK macros).

/// Builds its value the first time it is asked for it.
template <class T>
class Lazy {
 public:
  explicit Lazy(std::function<T()> make) : make_(std::move(make)) {}
  const T& get() {
    if (!value_) value_ = make_();
    return *value_;
  }

 private:
  std::function<T()> make_;
  std::optional<T> value_;
};

template <class T>
std::shared_ptr<Lazy<T>> lazy(std::function<T()> make) {
  return std::make_shared<Lazy<T>>(std::move(make));
}

}  // namespace areamatch_bench
