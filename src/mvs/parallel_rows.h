// Row-parallel loops on std::thread: rows are handed out in small chunks
// through an atomic counter, so threads stay busy on uneven rows. Results
// must not depend on the thread count (callers use per-pixel random seeds).
#pragma once

#include <algorithm>
#include <atomic>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace colmap_lidar {

inline int ResolveNumThreads(int num_threads) {
  if (num_threads > 0) {
    return num_threads;
  }
  return std::max(1u, std::thread::hardware_concurrency());
}

// Calls fn(row) for row in [0, num_rows); the first exception is rethrown.
inline void ParallelForRows(int num_rows, int num_threads,
                            const std::function<void(int)>& fn) {
  const int threads = std::min(ResolveNumThreads(num_threads), num_rows);
  if (threads <= 1) {
    for (int row = 0; row < num_rows; ++row) fn(row);
    return;
  }
  constexpr int kChunk = 4;
  std::atomic<int> next(0);
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&] {
    try {
      for (;;) {
        const int begin = next.fetch_add(kChunk);
        if (begin >= num_rows) break;
        const int end = std::min(begin + kChunk, num_rows);
        for (int row = begin; row < end; ++row) fn(row);
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(error_mutex);
      if (!error) error = std::current_exception();
      next.store(num_rows);
    }
  };
  std::vector<std::thread> pool;
  for (int i = 1; i < threads; ++i) pool.emplace_back(worker);
  worker();
  for (std::thread& thread : pool) thread.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace colmap_lidar
