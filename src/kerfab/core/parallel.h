#pragma once
// Work spread over threads that still finishes when the machine will not start them.

#include <algorithm>
#include <atomic>
#include <exception>
#include <system_error>
#include <thread>
#include <vector>

namespace kerfab {

/// Runs work(id) for every id in [0, n): id 0 on the caller, each other on its own thread where
/// one can be started (under a memory limit it may not), the rest on the caller after id 0.
/// `work` must not throw; it may take the work of ids that never ran (a shared queue).
template <class Work>
void run_parallel(int n, const Work& work) {
  std::vector<std::jthread> pool;
  int started = 1;
  for (; started < n; ++started) {
    try {
      pool.emplace_back(work, started);
    } catch (const std::system_error&) {
      break;
    }
  }
  work(0);
  for (int id = started; id < n; ++id) work(id);
}

/// The machine's hardware threads, at least 1.
inline int hardware_threads() {
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

/// work(i) for every i in [0, n), taken from a shared queue by up to \p threads threads (at
/// most n). A thread whose work throws stops taking more; once all are done, the first
/// exception (by thread) is rethrown here.
template <class Work>
void for_each_index(int n, int threads, const Work& work) {
  threads = std::clamp(threads, 1, std::max(1, n));
  std::atomic<int> next{0};
  std::vector<std::exception_ptr> errors(threads);
  run_parallel(threads, [&](int id) {
    try {
      for (int i = next++; i < n; i = next++) work(i);
    } catch (...) {
      errors[id] = std::current_exception();
    }
  });
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace kerfab
