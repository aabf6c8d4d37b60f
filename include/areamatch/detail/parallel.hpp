#pragma once
/// \file detail/parallel.hpp
/// Independent pieces of work on a few threads, with results that do not depend on the thread
/// count (each piece writes only its own slot).

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace areamatch::detail {

/// The number of threads a `threads` parameter asks for: 0 means one per hardware thread (at least one).
inline unsigned resolved_threads(unsigned threads) {
  return threads == 0 ? std::max(1u, std::thread::hardware_concurrency()) : threads;
}

/// Calls `work(i)` for every i < count on `threads` threads (0: the hardware's count). When
/// pieces throw, the exception of the lowest index is rethrown once all threads have stopped —
/// the one a single thread would have met first, so errors do not depend on the thread count.
template <class Work>
void for_each_index(std::size_t count, unsigned threads, const Work& work) {
  threads = static_cast<unsigned>(std::min<std::size_t>(resolved_threads(threads), count));
  if (threads <= 1) {
    for (std::size_t i = 0; i < count; ++i) work(i);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::size_t failed_index = count;
  std::mutex failure_mutex;
  auto worker = [&] {
    for (std::size_t i; (i = next.fetch_add(1)) < count;) {
      try {
        work(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failure_mutex);
        if (i < failed_index) failure = std::current_exception(), failed_index = i;
        next = count;  // hand out nothing more: every lower index is already handed out
      }
    }
  };
  std::vector<std::thread> pool;
  try {
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
  } catch (const std::system_error&) {  // fewer threads than asked: the work is still all done
  }
  worker();
  for (auto& thread : pool) thread.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace areamatch::detail
