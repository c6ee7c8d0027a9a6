#pragma once
// Shear strength of an intact contact bond in compression (N), shared by the contact law
// (when the bond breaks) and the creep law (how loaded the bond is, for its corrosion):
//
//   S = (ss + e Fn)(1 - D) + (mu_b - e) Fn,   e = max(mu_b - mu, 0),   Fn >= 0
//
// ss the bond's shear strength (N), mu_b its friction, mu the grains' friction, D its
// corrosion damage. With mu_b <= mu (PFC's contact bond: mu_b = 0; the Mohr-Coulomb bond
// with the grains' friction) this is ss (1 - D) + mu_b Fn: corrosion takes the cohesion
// only. A cemented contact whose bond friction exceeds the grains' (cement interlock: the
// cement's asperities lock the grains, as the higher peak friction angle of cemented
// sands shows) carries the excess e Fn in the cement too, so it fades with the damage:
// a fully corroded bond (D = 1) is a plain frictional contact of friction mu.
#include <algorithm>

namespace triax {

inline double bond_shear_strength(double ss, double mu_b, double mu, double fn, double damage) {
    const double f = std::max(fn, 0.0);
    const double excess = std::max(mu_b - mu, 0.0);
    return (ss + excess * f) * (1.0 - damage) + (mu_b - excess) * f;
}

// Rolling moment (N m) an intact bond's uncracked cement neck holds before it cracks:
// (mu_r + mu_rb (1 - D)) Rbar max(Fn, 0), mu_r the contact's rolling friction, mu_rb the
// neck's (bond_rolling_friction), Rbar the effective radius (m). Shared by the contact law
// (when the neck cracks) and the creep law (how loaded the neck is, for its corrosion).
inline double bond_neck_moment_limit(double mu_r, double mu_rb, double r_bar, double fn, double damage) {
    return (mu_r + mu_rb * (1.0 - damage)) * r_bar * std::max(fn, 0.0);
}

}  // namespace triax
