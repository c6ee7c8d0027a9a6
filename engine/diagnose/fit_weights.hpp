#pragma once
// Weights of the kinds of test in the fit (generalised least squares over kinds).
//
// A dataset with shear curves and creep stages pools two kinds of reading whose packing
// scatter at the calibration size differs by an order of magnitude (outside suite, creep
// sets: shear 6 %, creep stages 59-75 % NRMSE, where stages near failure burst on some
// packings). Pooled with equal weight, the 400 creep readings outvote the 240 shear ones
// and the base buys creep by weakening (friction 0.39 against 0.5, q_peak 116-159 against
// 198.6 kPa). Each kind's residuals are therefore scaled by
//
//   w_k = min(1, s_min / s_k),   s_k = max(model_nrmse_per_kind[k], lab_nrmse, kMinimumKindScatter),
//
// the least scattered kind keeping weight 1, so RSS, BIC and the paired gains count a
// reading by what a change of packing leaves of it. The weights are uniform (all 1) when
// one kind only was measured or the kinds' scatters are within kReweighRatio of each
// other: a shear-only dataset is fitted as before. Errors, the noise floor and the
// remaining misfit are reported on the unweighted residuals.
#include <string>
#include <utility>
#include <vector>

#include "engine/diagnose/noise_floor.hpp"
#include "engine/diagnose/residuals.hpp"

namespace triax::diagnose {

inline constexpr double kMinimumKindScatter = 0.02;  // NRMSE: below it reading noise and roughness rule
inline constexpr double kReweighRatio = 2.0;         // scatter ratio between kinds that calls for weights

using KindWeights = std::vector<std::pair<std::string, double>>;  // kind ("shear", "creep"), weight

// The weights from a measured noise floor; empty when they would all be 1.
KindWeights kind_weights(const NoiseFloor& noise);

// One weight per reading of the stacked residual (layout order); empty for no weights.
std::vector<double> reading_weights(const std::vector<ResidualSeries>& layout, const KindWeights& weights);

// A weighted residual back on the readings' own scale; a reading at the weighted penalty
// reads kUnreachedPenalty exactly (is_unreached). Weights of another length: r as it is.
std::vector<double> unweighted(std::vector<double> r, const std::vector<double>& weights);

}  // namespace triax::diagnose
