#include "colmap_ext/util/resource_usage.h"

#include <cstring>
#include <memory>
#include <vector>

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

#if defined(__SANITIZE_ADDRESS__)
#define COLMAP_LIDAR_SANITIZED_ALLOCATOR 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer) || \
    __has_feature(thread_sanitizer)
#define COLMAP_LIDAR_SANITIZED_ALLOCATOR 1
#endif
#endif

// Small blocks come from the heap, where freed memory between live blocks
// stays with the allocator; a reset hands it back first, so that the next
// stage's peak counts what is live.
TEST(ResourceUsage, ResetReturnsFreedHeapMemory) {
#if defined(COLMAP_LIDAR_SANITIZED_ALLOCATOR)
  GTEST_SKIP() << "a sanitizer's allocator keeps freed blocks in quarantine";
#endif
  ASSERT_TRUE(ResetPeakMemory());
  std::vector<std::unique_ptr<char[]>> blocks(200000);
  for (std::unique_ptr<char[]>& block : blocks) {
    block.reset(new char[1000]);
    std::memset(block.get(), 1, 1000);
  }
  const size_t with_all = ProcessPeakMemoryBytes();
  // One block in 64 stays: the heap cannot shrink from its top.
  for (size_t i = 0; i < blocks.size(); ++i) {
    if (i % 64 != 0) blocks[i].reset();
  }
  ASSERT_TRUE(ResetPeakMemory());
  EXPECT_LT(ProcessPeakMemoryBytes() + 120 * kMiB, with_all);
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
