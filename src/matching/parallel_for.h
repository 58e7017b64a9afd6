// A minimal parallel-for over [begin, end) with std::thread for the
// matching stage: indices are handed out from an atomic counter (views have
// very different numbers of segments); the first exception is rethrown on
// the calling thread after all workers stopped.
#pragma once

#include <algorithm>
#include <atomic>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace colmap_lidar {

// num_threads <= 0: std::thread::hardware_concurrency().
inline void MatchingParallelFor(int begin, int end, int num_threads,
                                const std::function<void(int)>& function) {
  if (num_threads <= 0) {
    num_threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  }
  num_threads = std::max(1, std::min(num_threads, end - begin));
  if (num_threads <= 1) {
    for (int i = begin; i < end; ++i) function(i);
    return;
  }
  std::atomic<int> next(begin);
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&]() {
    while (true) {
      const int i = next.fetch_add(1);
      if (i >= end) return;
      try {
        function(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        next.store(end);
        return;
      }
    }
  };
  std::vector<std::thread> threads;
  for (int t = 0; t < num_threads; ++t) threads.emplace_back(worker);
  for (std::thread& thread : threads) thread.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace colmap_lidar
