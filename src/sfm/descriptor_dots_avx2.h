// The AVX2 + FMA build of DescriptorDots (descriptor_dots.h), exported from
// its own shared library, which descriptor_dots.cc loads with dlopen and
// calls only when the CPU has AVX2 and FMA.
#pragma once

extern "C" {
__attribute__((visibility("default"))) void ColmapLidarDescriptorDotsAvx2(
    const float* rows1, int num_rows, const float* cols2, int num_cols,
    int dims, float* dots);
}
