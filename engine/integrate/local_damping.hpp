#pragma once
// PFC local (non-viscous) damping: each component of the unbalanced force is reduced
// by alpha |F| in the direction that opposes the motion,
//   F_d = F - alpha |F| sign(v)   (componentwise; sign(0) = 0).
// The dissipated power is (F - F_d) . v. For a 1-d elastic impact it gives the
// restitution e = sqrt((1 - alpha) / (1 + alpha)) (compression phase sees k (1 + alpha),
// restitution phase k (1 - alpha)).
#include "engine/core/types.hpp"

#include <cmath>

namespace triax {

// Branch-free (the signs of the velocity components are random from particle to
// particle, so a branch mispredicts often); exactly 1, -1 or 0 (also 0 for NaN), as the
// conditional form gave.
inline double sign_of(double v) { return static_cast<double>(v > 0.0) - static_cast<double>(v < 0.0); }

inline Vec3 local_damping_force(const Vec3& f, const Vec3& v, double alpha) {
    return Vec3(f[0] - alpha * std::abs(f[0]) * sign_of(v[0]),
                f[1] - alpha * std::abs(f[1]) * sign_of(v[1]),
                f[2] - alpha * std::abs(f[2]) * sign_of(v[2]));
}

}  // namespace triax
