// A thread that logs, once per period, that a long step is still running:
// its name, the elapsed time and, when the step reports it, its progress.
// The mesher's steps (triangulation, ray casting, max-flow) have no callback
// of their own and can run for minutes on large scenes (KITTI); the log then
// shows what runs and how far it got instead of nothing.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

namespace colmap_lidar {

class ProgressWatchdog {
 public:
  // Starts logging "<step>: still running after N s" every `period`
  // (> 0), with "done / total <unit>" when SetTotal was called. The step
  // ends (and the thread joins) on destruction.
  explicit ProgressWatchdog(
      std::string step,
      std::chrono::milliseconds period = std::chrono::seconds(60));
  ~ProgressWatchdog();
  ProgressWatchdog(const ProgressWatchdog&) = delete;
  ProgressWatchdog& operator=(const ProgressWatchdog&) = delete;

  // Progress of the step, in `unit`s; cheap and thread-safe. A total of 0
  // logs only the done count.
  void SetTotal(uint64_t total, const std::string& unit);
  void SetDone(uint64_t done) { done_.store(done, std::memory_order_relaxed); }
  void AddDone(uint64_t delta) {
    done_.fetch_add(delta, std::memory_order_relaxed);
  }

  // Number of lines logged so far.
  int NumReports() const { return num_reports_.load(); }

 private:
  void Run();

  const std::string step_;
  const std::chrono::milliseconds period_;
  const std::chrono::steady_clock::time_point start_;
  std::atomic<uint64_t> done_{0};
  std::atomic<uint64_t> total_{0};
  std::string unit_;  // Guarded by mutex_.
  std::atomic<int> num_reports_{0};
  std::mutex mutex_;
  std::condition_variable stop_condition_;
  bool stop_ = false;  // Guarded by mutex_.
  std::thread thread_;
};

}  // namespace colmap_lidar
