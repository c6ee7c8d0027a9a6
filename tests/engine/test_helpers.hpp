#pragma once
// Small builders shared by the engine tests.
#include "engine/core/world.hpp"

#include <cmath>

namespace triax::test {

constexpr double kPi = 3.14159265358979323846;

inline ContactLaw linear_law(double kn, double ks, double mu) {
    ContactLaw law;
    law.kn = kn;
    law.ks = ks;
    law.friction = mu;
    return law;
}

inline double sphere_mass(double r, double rho) { return rho * 4.0 / 3.0 * kPi * r * r * r; }

}  // namespace triax::test
