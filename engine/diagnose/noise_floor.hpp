#pragma once
// What a perfect model could not fit: the scatter of the model between packings of the same
// material at the calibration size, and the reading noise of the lab curves. Both in NRMSE
// units (share of each lab curve's range), so they compare with the pooled residual.
//
//   model_nrmse     = sqrt(mean over readings of Var_seeds[model value] / scale^2), from the
//                     same parameters run on several packings (seeds);
//   lab_nrmse       = sqrt(mean over readings of d_i^2 / (1 + w^2 + (1 - w)^2)) / scale, with
//                     d_i a reading's departure from the line through its two neighbours
//                     (abscissa log t for creep) and w its interpolation weight: the white
//                     reading noise, not the curve's shape, when readings are dense;
//   tolerance_nrmse = sqrt(2 model^2 + lab^2): the expected NRMSE of a right model fitted on
//                     one packing to a specimen that is another packing, read with noise.
// The diagnosis names an effect only if it lowers the pooled NRMSE by more than
// model_nrmse (a change of packing could give as much), and calls a residual unexplained
// only if it stays above kUnexplainedFactor x tolerance (docs/diagnosis.md).
#include <string>
#include <utility>
#include <vector>

namespace triax::diagnose {

struct ResidualSeries;  // residuals.hpp

struct NoiseFloor {
    int seeds = 0;                 // packings behind model_nrmse (0: not measured)
    double model_nrmse = 0.0;
    double lab_nrmse = 0.0;
    double tolerance_nrmse = 0.0;
    std::vector<std::pair<std::string, double>> model_nrmse_per_curve;  // label, NRMSE
    // The same pooled over the curves of one kind of test, "shear" (deviator and volumetric
    // curves) and "creep" (creep stages and their instant series): a creep stage that
    // bursts on one packing widens the creep curves' limits, not the shear curves'.
    std::vector<std::pair<std::string, double>> model_nrmse_per_kind;  // kind, NRMSE
    // The pooled-NRMSE gain a change had to exceed to be named: the median, over the
    // candidates and artefacts tested, of their paired gains' spread across packings (0: no
    // paired gain measured). The smallest effect this diagnosis could have named.
    double smallest_nameable_gain = 0.0;
};

// The kind of test a curve label belongs to: "creep" for "creep-N@..." and "instant@...",
// else "shear".
std::string curve_kind(const std::string& label);

// The lab curves' reading noise (pooled over the layout).
double lab_reading_noise(const std::vector<ResidualSeries>& layout);

// From residual vectors of one parameter set on several packings (empty vectors, failed
// runs, are skipped; readings any run did not reach are skipped).
NoiseFloor noise_floor(const std::vector<ResidualSeries>& layout, const std::vector<std::vector<double>>& replicates);

}  // namespace triax::diagnose
