#pragma once
// The four-lane vocabulary of the engine's SIMD kernels (core/step/frictional_lanes.cpp,
// integrate/sphere_lanes.cpp): four doubles and the mask of a comparison (all ones where
// true) as GCC/Clang vector extensions, one AVX register each, and 3-vectors of them.
//
// Include only from a file built with -ffp-contract=off (no FMA contraction) whose kernels
// carry TRIAX_LANES' target: every helper performs the scalar (Eigen) operation in its
// order, lane by lane (dot and squared norm as (x x + y y) + z z, checked against Eigen on
// 10^6 random vectors), so a lane gets the scalar path's bits. Lowered to SSE2 pairs, the
// contact kernel ran 0.70x the scalar law's speed, so these are compiled for AVX2 only and
// the helpers carry the kernels' target: their 32-byte arguments then pass in AVX registers.
#include "engine/core/simd/avx2.hpp"
#include "engine/core/types.hpp"

#include <vector>

#define TRIAX_LANES [[gnu::target("avx2"), gnu::always_inline]] inline

namespace triax::simd {

typedef double Lanes __attribute__((vector_size(32)));
typedef long long Mask __attribute__((vector_size(32)));

struct Vec3Lanes {
    Lanes x, y, z;
};

TRIAX_LANES Lanes broadcast(double v) { return Lanes{v, v, v, v}; }
TRIAX_LANES Vec3Lanes broadcast(const Vec3& v) { return {broadcast(v.x()), broadcast(v.y()), broadcast(v.z())}; }
TRIAX_LANES Vec3Lanes operator+(const Vec3Lanes& a, const Vec3Lanes& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
TRIAX_LANES Vec3Lanes operator-(const Vec3Lanes& a, const Vec3Lanes& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
TRIAX_LANES Vec3Lanes operator-(const Vec3Lanes& a) { return {-a.x, -a.y, -a.z}; }
TRIAX_LANES Vec3Lanes operator*(const Vec3Lanes& a, Lanes s) { return {a.x * s, a.y * s, a.z * s}; }
TRIAX_LANES Vec3Lanes operator*(Lanes s, const Vec3Lanes& a) { return {s * a.x, s * a.y, s * a.z}; }
TRIAX_LANES Lanes dot(const Vec3Lanes& a, const Vec3Lanes& b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }
TRIAX_LANES Vec3Lanes cross(const Vec3Lanes& a, const Vec3Lanes& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
TRIAX_LANES Vec3Lanes select(Mask m, const Vec3Lanes& a, const Vec3Lanes& b) {
    return {m ? a.x : b.x, m ? a.y : b.y, m ? a.z : b.z};
}
TRIAX_LANES bool any(Mask m) { return (m[0] | m[1] | m[2] | m[3]) != 0; }
// Correctly rounded per lane (vsqrtsd or vsqrtpd: the same bits).
TRIAX_LANES Lanes sqrt_lanes(Lanes v) {
    Lanes r;
    for (int l = 0; l < kLaneCount; ++l) r[l] = __builtin_sqrt(v[l]);
    return r;
}
TRIAX_LANES Lanes abs_lanes(Lanes v) {
    Lanes r;
    for (int l = 0; l < kLaneCount; ++l) r[l] = __builtin_fabs(v[l]);
    return r;
}
// std::max(a, b) per lane: b where a < b, else a (also a where b is NaN).
TRIAX_LANES Lanes max_lanes(Lanes a, Lanes b) { return a < b ? b : a; }

// a[idx[0..3]], any index type.
template <class Index>
TRIAX_LANES Vec3Lanes gather(const std::vector<Vec3>& a, const Index* idx) {
    Vec3Lanes r;
    for (int l = 0; l < kLaneCount; ++l) {
        const Vec3& v = a[idx[l]];
        r.x[l] = v.x();
        r.y[l] = v.y();
        r.z[l] = v.z();
    }
    return r;
}
// Four consecutive entries a[0..3].
TRIAX_LANES Vec3Lanes load(const Vec3* a) {
    Vec3Lanes r;
    for (int l = 0; l < kLaneCount; ++l) {
        r.x[l] = a[l].x();
        r.y[l] = a[l].y();
        r.z[l] = a[l].z();
    }
    return r;
}
TRIAX_LANES Lanes load(const double* a) { return Lanes{a[0], a[1], a[2], a[3]}; }
TRIAX_LANES Vec3 lane(const Vec3Lanes& v, int l) { return Vec3(v.x[l], v.y[l], v.z[l]); }
TRIAX_LANES void store(const Vec3Lanes& v, Vec3* a) {
    for (int l = 0; l < kLaneCount; ++l) a[l] = lane(v, l);
}
TRIAX_LANES void store(Lanes v, double* a) {
    for (int l = 0; l < kLaneCount; ++l) a[l] = v[l];
}

}  // namespace triax::simd
