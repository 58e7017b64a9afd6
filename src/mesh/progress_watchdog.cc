#include "src/mesh/progress_watchdog.h"

#include <iomanip>
#include <sstream>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

ProgressWatchdog::ProgressWatchdog(std::string step,
                                   std::chrono::milliseconds period)
    : step_(std::move(step)),
      period_(period),
      start_(std::chrono::steady_clock::now()) {
  THROW_CHECK(period_.count() > 0, "ProgressWatchdog: period must be > 0");
  thread_ = std::thread(&ProgressWatchdog::Run, this);
}

ProgressWatchdog::~ProgressWatchdog() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  stop_condition_.notify_all();
  thread_.join();
}

void ProgressWatchdog::SetTotal(uint64_t total, const std::string& unit) {
  std::lock_guard<std::mutex> lock(mutex_);
  unit_ = unit;
  total_.store(total, std::memory_order_relaxed);
}

void ProgressWatchdog::Run() {
  std::unique_lock<std::mutex> lock(mutex_);
  auto next = start_ + period_;
  while (!stop_condition_.wait_until(lock, next, [this] { return stop_; })) {
    next += period_;
    const double elapsed = std::chrono::duration<double>(
                               std::chrono::steady_clock::now() - start_)
                               .count();
    std::ostringstream line;
    line << step_ << ": still running after " << std::fixed
         << std::setprecision(0) << elapsed << " s";
    const uint64_t done = done_.load(std::memory_order_relaxed);
    const uint64_t total = total_.load(std::memory_order_relaxed);
    if (total > 0) {
      line << ", " << done << " / " << total << " " << unit_ << " ("
           << std::setprecision(1) << 100.0 * done / total << " %)";
    } else if (done > 0 || !unit_.empty()) {
      line << ", " << done << " " << unit_;
    }
    LOG(INFO) << line.str();
    ++num_reports_;
  }
}

}  // namespace colmap_lidar
