#include "colmap_ext/util/resource_usage.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/resource.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace colmap_lidar {
namespace {

std::atomic<size_t> child_peak_bytes{0};

double SteadySeconds() {
  return std::chrono::duration<double>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

double TimevalSeconds(const timeval& time) {
  return static_cast<double>(time.tv_sec) + 1e-6 * time.tv_usec;
}

}  // namespace

size_t ProcessPeakMemoryBytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) {
      std::istringstream fields(line.substr(6));
      size_t kib = 0;
      fields >> kib;
      return kib * 1024;
    }
  }
  return 0;
}

double ProcessCpuSeconds() {
  double seconds = 0.0;
  for (const int who : {RUSAGE_SELF, RUSAGE_CHILDREN}) {
    rusage usage{};
    if (getrusage(who, &usage) == 0) {
      seconds += TimevalSeconds(usage.ru_utime) + TimevalSeconds(usage.ru_stime);
    }
  }
  return seconds;
}

bool ResetPeakMemory() {
  child_peak_bytes = 0;
#if defined(__GLIBC__)
  // glibc keeps freed small blocks in its arenas (only the top of a heap
  // goes back by itself): what an earlier stage freed would stay resident
  // and count in the next stage's peak, and crowd the stock colmap children
  // that the next stage starts.
  malloc_trim(0);
#endif
  std::ofstream clear_refs("/proc/self/clear_refs");
  if (!clear_refs) {
    return false;
  }
  clear_refs << "5";
  clear_refs.flush();
  return static_cast<bool>(clear_refs);
}

size_t ChildPeakMemoryBytes() { return child_peak_bytes.load(); }

void RecordChildPeakMemory(const size_t bytes) {
  size_t previous = child_peak_bytes.load();
  while (previous < bytes &&
         !child_peak_bytes.compare_exchange_weak(previous, bytes)) {
  }
}

ResourceTimer::ResourceTimer() {
  ResetPeakMemory();
  wall_start_ = SteadySeconds();
  cpu_start_ = ProcessCpuSeconds();
}

double ResourceTimer::WallSeconds() const {
  return SteadySeconds() - wall_start_;
}

double ResourceTimer::CpuSeconds() const {
  return ProcessCpuSeconds() - cpu_start_;
}

size_t ResourceTimer::PeakMemoryBytes() const {
  return std::max(ProcessPeakMemoryBytes(), ChildPeakMemoryBytes());
}

}  // namespace colmap_lidar
