#pragma once
// The CLI's progress line: a long run (more than about a second) says on stderr which stage it
// is in and for how long, redrawn in place and cleared when the run ends — only when stderr is a
// terminal (never into a pipe or a file, so never into --json output or a log).
// AREAMATCH_PROGRESS=always draws it whatever stderr is and from the start, =never never draws it.

#include <areamatch/progress.hpp>

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>

#include <unistd.h>

namespace areamatch_cli {

/// What a stage of `areamatch::Progress` is called on the line.
inline std::string stage_words(const areamatch::Progress& p) {
  const std::string_view s = p.stage;
  std::string words = s == "load"      ? "loading the maps"
                      : s == "segment" ? "segmenting"
                      : s == "prepare" ? "pairing areas"
                      : s == "select"  ? "checking hypotheses"
                      : s == "check"   ? "measuring the answer"
                      : s == "scale"   ? "trying scales"
                      : s == "match"   ? "matching pairs of maps"
                      : s == "poses"   ? "fitting the poses"
                      : s == "warp"    ? "bending the maps"
                      : s == "fuse"    ? "fusing the maps"
                                       : std::string(s);
  if (p.total > 0) words += " " + std::to_string(p.done) + " / " + std::to_string(p.total);
  else if (s == "scale") words += " (" + std::to_string(p.done + 1) + ")";
  return words;
}

/// AREAMATCH_PROGRESS's value ("always", "never"), empty when unset or anything else.
inline std::string_view progress_setting() {
  const char* v = std::getenv("AREAMATCH_PROGRESS");
  const std::string_view value = v ? v : "";
  return value == "always" || value == "never" ? value : std::string_view();
}

/// One command's progress line; `callback()` feeds it. Drawn from a second thread ten times a
/// second once the run has taken `delay`, so the time moves while a long stage runs.
class ProgressLine {
 public:
  explicit ProgressLine(std::string command, std::chrono::milliseconds delay = std::chrono::milliseconds(1000))
      : command_(std::move(command)), delay_(delay), start_(std::chrono::steady_clock::now()) {
    const std::string_view setting = progress_setting();
    if (setting == "always") delay_ = std::chrono::milliseconds(0);
    if (setting == "always" || (setting.empty() && isatty(fileno(stderr)) != 0)) ticker_ = std::thread([this] { tick(); });
  }
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;
  ~ProgressLine() { finish(); }

  /// The library's reports, for `Matcher::progress`.
  areamatch::ProgressCallback callback() {
    return [this](const areamatch::Progress& p) { set(stage_words(p)); };
  }
  void set(std::string words) {
    const std::lock_guard<std::mutex> lock(mutex_);
    words_ = std::move(words);
  }
  /// Stops drawing and clears the line (before the command prints its own output): the line
  /// is redrawn in place with a carriage return and erased with ESC [K.
  void finish() {
    if (!ticker_.joinable()) return;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      done_ = true;
    }
    wake_.notify_all();
    ticker_.join();
    if (drawn_) std::fputs("\r\033[K", stderr);
    std::fflush(stderr);
  }

 private:
  void tick() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!wake_.wait_for(lock, std::chrono::milliseconds(100), [this] { return done_; })) {
      const auto elapsed = std::chrono::steady_clock::now() - start_;
      if (elapsed < delay_ || words_.empty()) continue;
      const double seconds = std::chrono::duration<double>(elapsed).count();
      char time[32];
      std::snprintf(time, sizeof time, "%.1f s", seconds);
      std::fprintf(stderr, "\r\033[K%s: %s (%s)", command_.c_str(), words_.c_str(), time);
      std::fflush(stderr);
      drawn_ = true;
    }
  }

  std::string command_;
  std::chrono::milliseconds delay_;
  std::chrono::steady_clock::time_point start_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::string words_;
  bool done_ = false;
  bool drawn_ = false;
  std::thread ticker_;
};

}  // namespace areamatch_cli
