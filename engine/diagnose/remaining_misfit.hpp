#pragma once
// Is what remains after the fit within what a right model leaves? The outcome rule of the
// diagnosis (docs/diagnosis.md section 9), apart from the loop so it can be tested on its
// own. NRMSE values are fractions of each lab series' range.
#include <vector>

#include "engine/diagnose/diagnosis.hpp"
#include "engine/diagnose/noise_floor.hpp"

namespace triax::diagnose {

struct RemainingMisfit {
    bool unexplained = false;
    // Where it remains: the worst curve phase (n >= 5) if it is beyond its limit, else the
    // curve furthest beyond its own limit, else the worst phase.
    PhaseError where;
};

// Unexplained when the pooled NRMSE exceeds max(2 tau, 5 %), or a phase of >= 5 readings
// exceeds twice that, or one curve exceeds max(2 tau_c, 5 %), tau_c = sqrt(2 s_c^2 + s_lab^2)
// with s_c the curve's own packing scatter floored at that of its kind of test (shear
// or creep curves pooled; the pooled scatter when the kind's is not measured). Curves count from 5
// readings, a creep pressure's instant series (one reading per stage) from 3.
RemainingMisfit judge_remaining(const std::vector<PhaseError>& error_after, double nrmse_after, const NoiseFloor& noise);

}  // namespace triax::diagnose
