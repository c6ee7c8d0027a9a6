#pragma once
// Whether this CPU runs the engine's four-lane kernels (AVX2), and their width. Safe to
// include anywhere: the kernels themselves (simd/lanes.hpp) are compiled for AVX2 in their
// own files and called only where avx2_available() is true; elsewhere the scalar paths
// run, with the same bits.
namespace triax::simd {

constexpr int kLaneCount = 4;  // doubles per AVX2 register

// Checked once per process (the CPUID bit), then a load.
bool avx2_available();

}  // namespace triax::simd
