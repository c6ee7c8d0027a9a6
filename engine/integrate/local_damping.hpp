#pragma once
// PFC local (non-viscous) damping: each component of the unbalanced force is reduced
// by alpha |F| in the direction that opposes the motion,
//   F_d = F - alpha |F| sign(v)   (componentwise; sign(0) = 0).
// The dissipated power is (F - F_d) . v. For a 1-d elastic impact it gives the
// restitution e = sqrt((1 - alpha) / (1 + alpha)) (compression phase sees k (1 + alpha),
// restitution phase k (1 - alpha)).
#include "engine/core/types.hpp"

#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace triax {

// Branch-free (the signs of the velocity components are random from particle to
// particle, so a branch mispredicts often); exactly 1, -1 or 0 (also 0 for NaN), as the
// conditional form gives. A compiler may turn the portable form below into a compare and
// a branch on v > 0, so on x86 the two compares are mask operations: an ordered
// compare gives an all-ones mask or zero, AND 1.0 gives 1.0 or +0.0, and the difference
// is the same +1, -1 or +0.0 (NaN: both compares false, +0.0).
inline double sign_of(double v) {
#if defined(__SSE2__)
    const __m128d x = _mm_set_sd(v), zero = _mm_setzero_pd(), one = _mm_set_sd(1.0);
    const __m128d pos = _mm_and_pd(_mm_cmpgt_sd(x, zero), one);
    const __m128d neg = _mm_and_pd(_mm_cmplt_sd(x, zero), one);
    return _mm_cvtsd_f64(_mm_sub_sd(pos, neg));
#else
    return static_cast<double>(v > 0.0) - static_cast<double>(v < 0.0);
#endif
}

inline Vec3 local_damping_force(const Vec3& f, const Vec3& v, double alpha) {
    return Vec3(f[0] - alpha * std::abs(f[0]) * sign_of(v[0]),
                f[1] - alpha * std::abs(f[1]) * sign_of(v[1]),
                f[2] - alpha * std::abs(f[2]) * sign_of(v[2]));
}

}  // namespace triax
