// Wall time, CPU time and peak memory of a piece of work in this process and
// in the child processes it waited for (stock colmap runs), for the stage
// timings of the pipeline and its report.
//
// Peak memory: Linux keeps the peak resident set size of a process (VmHWM)
// and lets the process reset it (writing "5" to /proc/self/clear_refs, Linux
// >= 4.0), so the peak of one stage of a long process can be measured. A
// child's peak is taken from wait4()'s rusage when it ends
// (RecordChildPeakMemory, called by ColmapRunner), since getrusage's
// RUSAGE_CHILDREN peak cannot be reset.
#pragma once

#include <chrono>

#include <cstddef>

namespace colmap_lidar {

// VmHWM of /proc/self/status in bytes; 0 when unavailable.
size_t ProcessPeakMemoryBytes();

// CPU time (user + system) of this process plus all children it has waited
// for, seconds.
double ProcessCpuSeconds();

// Returns the heap's free pages to the system (glibc's malloc_trim), then
// resets this process's VmHWM to its current resident size and the child
// peak below to 0. Returns false when the kernel does not allow the reset
// (the process peak then stays cumulative).
bool ResetPeakMemory();

// Largest peak resident size of a child since the last reset, bytes.
size_t ChildPeakMemoryBytes();
// Called with a finished child's ru_maxrss converted to bytes.
void RecordChildPeakMemory(size_t bytes);

// Wall seconds since `start` (steady clock).
inline double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                       start)
      .count();
}

// Measures from construction: wall and CPU seconds, and (after
// ResetPeakMemory() in the constructor) the peak of this process and of its
// children.
class ResourceTimer {
 public:
  ResourceTimer();

  double WallSeconds() const;
  double CpuSeconds() const;
  // max(process peak, child peak) since construction, bytes.
  size_t PeakMemoryBytes() const;

 private:
  double wall_start_;
  double cpu_start_;
};

}  // namespace colmap_lidar
