#include "colmap_ext/util/resource_usage.h"

#include <cstring>
#include <memory>

#include <gtest/gtest.h>

namespace colmap_lidar {
namespace {

constexpr size_t kMiB = 1024 * 1024;

// Touches `bytes` of fresh memory so that they become resident, and frees
// them again.
void TouchAndFree(const size_t bytes) {
  std::unique_ptr<char[]> block(new char[bytes]);
  std::memset(block.get(), 1, bytes);
  volatile char sink = block[bytes / 2];
  (void)sink;
}

TEST(ResourceUsage, PeakFollowsAllocationsAndResets) {
  ResourceTimer timer;
  const size_t before = timer.PeakMemoryBytes();
  TouchAndFree(256 * kMiB);
  const size_t after = timer.PeakMemoryBytes();
  EXPECT_GE(after, before + 200 * kMiB);
  // The block is freed (large blocks go back to the system), so a reset
  // brings the peak back down.
  ASSERT_TRUE(ResetPeakMemory());
  EXPECT_LT(ProcessPeakMemoryBytes(), after - 200 * kMiB);
}

TEST(ResourceUsage, ChildPeakIsTheLargestSinceReset) {
  ResetPeakMemory();
  RecordChildPeakMemory(10 * kMiB);
  RecordChildPeakMemory(30 * kMiB);
  RecordChildPeakMemory(20 * kMiB);
  EXPECT_EQ(ChildPeakMemoryBytes(), 30 * kMiB);
  ResetPeakMemory();
  EXPECT_EQ(ChildPeakMemoryBytes(), 0u);
}

TEST(ResourceUsage, CpuAndWallTimeAdvance) {
  ResourceTimer timer;
  volatile double sum = 0.0;
  for (int i = 0; i < 50000000; ++i) {
    sum = sum + 1e-9 * i;
  }
  EXPECT_GT(timer.CpuSeconds(), 0.0);
  EXPECT_GT(timer.WallSeconds(), 0.0);
  EXPECT_LE(timer.CpuSeconds(), 2.0 * timer.WallSeconds() + 0.05);
}

}  // namespace
}  // namespace colmap_lidar
