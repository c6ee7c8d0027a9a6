#pragma once
// The score test that ranks effects (docs/diagnosis.md section 3): how much of the current
// residual r lies along an effect's signature s = r(with) - r(without) once the directions
// the current parameters can already produce (the columns of J) are projected out. Only the
// direction that reduces the residual counts (effects are switched on from zero):
//   score = max(0, -r.s_perp) / (|r| |s_perp|),
// taken over all readings and over each kind of test apart (shear curves; creep stages with
// their instant series), the largest of these.
#include <vector>

#include "engine/diagnose/residuals.hpp"

namespace triax::diagnose {

// residual, with_effect: stacked normalised residuals in layout order; jacobian: column-major
// n x k (k = jacobian.size() / n; empty or mis-sized: nothing is projected out). 0..1.
double signature_score(const std::vector<double>& residual, const std::vector<double>& with_effect,
                       const std::vector<double>& jacobian, const std::vector<ResidualSeries>& layout);

}  // namespace triax::diagnose
