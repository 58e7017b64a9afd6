// A minimal parallel-for over an index range with std::thread: indices are
// handed out one at a time from an atomic counter, which balances items of
// very different cost (image rows with sky vs. textured walls, views with
// few or many segments). The first exception thrown by `function` is
// rethrown on the calling thread after all workers stop.
#pragma once

#include <algorithm>
#include <atomic>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace colmap_lidar {

// num_threads <= 0 means std::thread::hardware_concurrency().
inline void ParallelFor(int begin, int end, int num_threads,
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
  threads.reserve(num_threads);
  for (int t = 0; t < num_threads; ++t) threads.emplace_back(worker);
  for (std::thread& thread : threads) thread.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace colmap_lidar
