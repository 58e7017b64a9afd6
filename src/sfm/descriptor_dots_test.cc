#include "src/sfm/descriptor_dots.h"

#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace colmap_lidar {
namespace {

// Descriptors with the largest values COLMAP stores (uint8, 255) in every
// dimension of some rows: the largest sums, 128 * 255^2, must stay exact.
struct Descriptors {
  int num_rows = 0;
  int num_cols = 0;
  int dims = 128;
  std::vector<float> rows1;  // num_rows x dims, row-major
  std::vector<float> cols2;  // dims x num_cols, column-major
  std::vector<int64_t> rows1_int;
  std::vector<int64_t> cols2_int;
};

Descriptors RandomDescriptors(int num_rows, int num_cols, uint32_t seed) {
  Descriptors d;
  d.num_rows = num_rows;
  d.num_cols = num_cols;
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> value(0, 255);
  d.rows1_int.resize(static_cast<size_t>(num_rows) * d.dims);
  d.cols2_int.resize(static_cast<size_t>(num_cols) * d.dims);
  for (int64_t& v : d.rows1_int) v = value(rng);
  for (int64_t& v : d.cols2_int) v = value(rng);
  for (int k = 0; k < d.dims; ++k) {
    d.rows1_int[k] = 255;                // row 0 all 255
    d.cols2_int[k] = 255;                // column 0 all 255
  }
  d.rows1.assign(d.rows1_int.begin(), d.rows1_int.end());
  d.cols2.assign(d.cols2_int.begin(), d.cols2_int.end());
  return d;
}

// The exact integer products, row-major.
std::vector<float> Reference(const Descriptors& d) {
  std::vector<float> dots(static_cast<size_t>(d.num_rows) * d.num_cols);
  for (int r = 0; r < d.num_rows; ++r) {
    for (int c = 0; c < d.num_cols; ++c) {
      int64_t sum = 0;
      for (int k = 0; k < d.dims; ++k) {
        sum += d.rows1_int[static_cast<size_t>(r) * d.dims + k] *
               d.cols2_int[static_cast<size_t>(c) * d.dims + k];
      }
      dots[static_cast<size_t>(r) * d.num_cols + c] = static_cast<float>(sum);
    }
  }
  return dots;
}

// Sizes that are not multiples of any kernel's blocks, and the matcher's
// block of 512 rows.
TEST(DescriptorDots, BothPathsGiveTheExactIntegerProducts) {
  for (const auto& [rows, cols] : {std::pair<int, int>{1, 1}, {7, 13},
                                   {37, 301}, {512, 203}}) {
    const Descriptors d = RandomDescriptors(rows, cols, 11u * rows + cols);
    const std::vector<float> expected = Reference(d);
    EXPECT_EQ(expected[0], 128.0f * 255.0f * 255.0f);
    std::vector<float> fast(expected.size(), -1.0f);
    std::vector<float> portable(expected.size(), -1.0f);
    DescriptorDots(d.rows1.data(), rows, d.cols2.data(), cols, d.dims,
                   fast.data());
    DescriptorDotsPortable(d.rows1.data(), rows, d.cols2.data(), cols, d.dims,
                           portable.data());
    // Bit for bit: the matcher's matches must not depend on the CPU.
    EXPECT_EQ(std::memcmp(fast.data(), expected.data(),
                          expected.size() * sizeof(float)), 0)
        << rows << " x " << cols << " on the " << DescriptorDotsPath()
        << " path";
    EXPECT_EQ(std::memcmp(portable.data(), expected.data(),
                          expected.size() * sizeof(float)), 0)
        << rows << " x " << cols << " on the portable path";
  }
}

// On a CPU with AVX2 and FMA the kernel's library loads (from the build
// tree): a broken build or load path would otherwise fall back silently.
TEST(DescriptorDots, TheAvx2KernelLoadsWhereTheCpuHasIt) {
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
    EXPECT_STREQ(DescriptorDotsPath(), "avx2");
  } else {
    EXPECT_STREQ(DescriptorDotsPath(), "portable");
  }
}

TEST(DescriptorDots, EmptyInputsWriteNothing) {
  std::vector<float> dots(4, -1.0f);
  const std::vector<float> rows1(128, 1.0f);
  DescriptorDots(rows1.data(), 0, rows1.data(), 1, 128, dots.data());
  DescriptorDots(rows1.data(), 1, rows1.data(), 0, 128, dots.data());
  EXPECT_EQ(dots, std::vector<float>(4, -1.0f));
}

}  // namespace
}  // namespace colmap_lidar
