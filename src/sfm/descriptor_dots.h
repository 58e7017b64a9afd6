// Dot products between two sets of SIFT descriptors, the inner loop of the
// exact matcher (exact_feature_matcher.h): dots = rows1 * cols2, with
// rows1 num_rows x dims (row-major) and cols2 dims x num_cols (column-
// major), dots num_rows x num_cols (row-major: the matcher scans each row).
//
// Why a kernel of its own: matching the 545 pairs of 60 corridor frames
// (1280x720, 3,500-6,400 SIFT features per image) spent 58 of its 146 CPU
// seconds in these products and their scan, with the SSE2 code that a
// portable build compiles Eigen to; built for AVX2 + FMA the same products
// take 0.042 instead of 0.134 s for 6,000 x 4,000 descriptors (3.2x). The
// AVX2 code is a shared library of its own (descriptor_dots_avx2.cc, hidden
// visibility) so that its Eigen instantiations, compiled for another ISA
// and another alignment, never replace the rest of the program's: one
// translation unit built with -march=x86-64-v3 inside the same binary made
// the matcher throw std::bad_alloc. It is loaded with dlopen on first use,
// only when the CPU reports AVX2 and FMA; where it cannot be loaded the
// portable path runs (one warning), so no command needs it to start.
//
// The result does not depend on the path: COLMAP's descriptors are integers
// in [0, 255], so every product and partial sum is an integer below 2^24
// (128 * 255^2 < 2^24) and exact in float whatever the order of the sums.
#pragma once

namespace colmap_lidar {

// Which path DescriptorDots takes on this CPU: "avx2" or "portable".
const char* DescriptorDotsPath();

// Writes num_rows x num_cols dot products into `dots` (row-major: row r,
// column j at dots[r * num_cols + j]), on the fastest path of this CPU. The
// inputs must hold integer values whose products sum below 2^24 for the
// result not to depend on the path (see above).
void DescriptorDots(const float* rows1, int num_rows, const float* cols2,
                    int num_cols, int dims, float* dots);

// The same on the portable path, whatever the CPU (tests compare the two).
void DescriptorDotsPortable(const float* rows1, int num_rows,
                            const float* cols2, int num_cols, int dims,
                            float* dots);

}  // namespace colmap_lidar
