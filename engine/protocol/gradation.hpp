#pragma once
// Particle radii from a GradationSpec.
// - RadiusRatio: radii uniform by number in [Rmin, Rmin * ratio] (PFC `ball distribute`
//   with the paper's Rmin = 0.5 mm and ratio 39.712, Eq. 3).
// - SieveCurve: each sieve interval is a size class holding its mass share; classes whose
//   upper size is below the fines cut-off are lumped into one class at their mass-weighted
//   mean radius r = sum R_i M_i / sum M_i (paper Eq. 2). Radii within a coarser class are
//   uniform between its sieve sizes; class counts follow the mass shares.
#include <cstdint>
#include <random>
#include <vector>

#include "engine/protocol/test_scheme.hpp"

namespace triax::protocol {

struct SizeClass {
    double r_lo_m = 0.0;
    double r_hi_m = 0.0;
    double mass_fraction = 0.0;
};

// Size classes of a gradation after lumping the fines (Eq. 2). Throws InputError on a
// non-monotonic sieve curve, naming the point index.
std::vector<SizeClass> size_classes(const GradationSpec& g);

// Mass-weighted mean radius of the fines below the cut-off (Eq. 2); 0 if none.
double weighted_fines_radius_m(const GradationSpec& g);

// Draws radii whose total solid volume reaches `solid_volume_m3` (the last particle may
// overshoot by one). Deterministic for a given rng state.
std::vector<double> draw_radii(const GradationSpec& g, double solid_volume_m3, std::mt19937_64& rng);

// Minimum and maximum radius the gradation can produce.
double gradation_r_min_m(const GradationSpec& g);
double gradation_r_max_m(const GradationSpec& g);

}  // namespace triax::protocol
