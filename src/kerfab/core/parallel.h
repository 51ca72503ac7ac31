#pragma once
// Work spread over threads that still finishes when the machine will not start them.

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

}  // namespace kerfab
