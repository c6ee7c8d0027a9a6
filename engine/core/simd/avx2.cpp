#include "engine/core/simd/avx2.hpp"

namespace triax::simd {

bool avx2_available() {
    static const bool avx2 = __builtin_cpu_supports("avx2");
    return avx2;
}

}  // namespace triax::simd
