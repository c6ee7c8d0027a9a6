#pragma once
// Stress level of a creep stage, both ways the paper uses it.
//   S_ratio = q / q_f                                   (Table 2 "stress level")
//   S_eq1   = q (1 - sin phi) / (2 c cos phi + 2 sigma3 sin phi)      (paper Eq. 1)
// Eq. 1 is q over the Mohr-Coulomb deviator at failure in compression: Mohr-Coulomb gives
// q_f = (2 c cos phi + 2 sigma3 sin phi) / (1 - sin phi), so S_eq1 = q / q_f(MC).
// Units: Pa and degrees in, dimensionless out.
#include <cmath>

namespace triax::protocol {

inline double mohr_coulomb_failure_deviator_pa(double sigma3_pa, double cohesion_pa, double phi_deg) {
    const double phi = phi_deg * 3.14159265358979323846 / 180.0;
    return (2.0 * cohesion_pa * std::cos(phi) + 2.0 * sigma3_pa * std::sin(phi)) / (1.0 - std::sin(phi));
}

inline double stress_level_eq1(double q_pa, double sigma3_pa, double cohesion_pa, double phi_deg) {
    return q_pa / mohr_coulomb_failure_deviator_pa(sigma3_pa, cohesion_pa, phi_deg);
}

inline double deviator_for_stress_level_eq1(double s, double sigma3_pa, double cohesion_pa, double phi_deg) {
    return s * mohr_coulomb_failure_deviator_pa(sigma3_pa, cohesion_pa, phi_deg);
}

}  // namespace triax::protocol
