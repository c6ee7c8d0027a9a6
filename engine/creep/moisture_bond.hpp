#pragma once
// Moisture content -> contact bond strength (docs/parameters.md). The paper links them
// through the yield stress; we use the common exponential softening of the yield stress
// of compacted fills wet of optimum (e.g. suction loss; Alonso-type LC-curve shapes):
//   sigma_y(w) = sigma_y(w_opt) * exp(-b_w (w - w_opt))   for w >= w_opt,
// and take bond strength proportional to sigma_y. Dry of optimum the strength is held at
// its optimum value (the paper only tests w >= w_opt). b_w = 15 per unit moisture (0.15 per
// percentage point) gives factors 0.82 at 10.2 % (group D) and 0.62 at 12.1 % (group E).
// The paper gives no numbers for it. A gentler relation does not buy D and E the paper's
// tertiary S = 0.8: at b_w = 2 E still converged there on two seeds of two (docs/creep.md,
// "Two more levers on the presets").
#include <algorithm>
#include <cmath>

namespace triax::creep {

constexpr double kOptimumMoisture = 0.089;      // Table 1
constexpr double kMoistureSoftening = 15.0;     // b_w, per unit moisture content

inline double bond_strength_factor(double moisture_content) {
    return std::exp(-kMoistureSoftening * std::max(0.0, moisture_content - kOptimumMoisture));
}

}  // namespace triax::creep
