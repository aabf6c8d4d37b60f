#pragma once
/// \file progress.hpp
/// How far a long run is: an optional callback that matching (`Matcher::progress`) and merging
/// call at the start of each stage. The library never prints; a program shows what it likes
/// (the CLI: one line on a terminal, after a second). A callback that throws stops the run, and
/// the exception reaches the caller: a way to cancel.
///
/// \code
/// areamatch::Matcher<> matcher;
/// matcher.progress = [](const areamatch::Progress& p) { std::cerr << p.stage << "\n"; };
/// \endcode

#include <cstddef>
#include <functional>
#include <mutex>
#include <string_view>

namespace areamatch {

/// One report: the stage that starts now and, where a stage has countable steps (the pairs of a
/// merge, the candidate scales of a scale search), how many of them are done.
struct Progress {
  /// What runs now: "load", "segment", "prepare", "select", "check" (matching); "match",
  /// "poses", "warp", "fuse" (merging); "scale" (a scale search). Static strings.
  std::string_view stage;
  std::size_t done = 0;   ///< steps of `stage` done so far
  std::size_t total = 0;  ///< steps of `stage` in all; 0 when it has no counted steps
};

/// Called at the start of each stage, one call at a time (never two at once), from the thread
/// that called the library or one of its worker threads; it must not change what it was given.
/// Results do not depend on it.
using ProgressCallback = std::function<void(const Progress&)>;

namespace detail {

/// Reports `stage` to `callback` when there is one.
inline void report(const ProgressCallback& callback, std::string_view stage, std::size_t done = 0, std::size_t total = 0) {
  if (callback) callback(Progress{stage, done, total});
}

/// Reports from several threads, one call at a time.
class SerialProgress {
 public:
  explicit SerialProgress(const ProgressCallback& callback) : callback_(callback) {}
  void operator()(std::string_view stage, std::size_t done = 0, std::size_t total = 0) {
    if (!callback_) return;
    const std::lock_guard<std::mutex> lock(mutex_);
    report(callback_, stage, done, total);
  }
  /// One more step of `stage` done, of `total`.
  void step(std::string_view stage, std::size_t total) {
    if (!callback_) return;
    const std::lock_guard<std::mutex> lock(mutex_);
    report(callback_, stage, ++done_, total);
  }

 private:
  const ProgressCallback& callback_;
  std::mutex mutex_;
  std::size_t done_ = 0;
};

}  // namespace detail
}  // namespace areamatch
