#pragma once
// The mean of one model point's curves over several packings (seeds). One packing of the
// calibration specimen (~200 grains) scatters by 5-30 % of a lab curve's range between
// seeds (docs/diagnosis.md section 6); the mean of K packings scatters 1/sqrt(K) as much, and
// it is the response a lab specimen of many more grains approaches.
//
// Curves are matched by kind, confining pressure and creep stage. Each averaged curve
// keeps the abscissa (axial strain, or time for creep) of the first packing that has it,
// cut where the shortest of those packings ends (a mean is never taken over a changing set
// of packings along one curve). A curve only some packings have (a creep stage after
// another packing's rupture) is the mean of those that have it.
#include <cstdint>
#include <vector>

#include "engine/diagnose/lab_data.hpp"

namespace triax::diagnose {

// Seed of packing j (j >= 1) of a model run with seed s: s + j * kPackingSeedStride; the
// stride keeps the packings apart from the noise floor's seeds (s + 1, s + 2, ...) and the
// retry's (s + 1000003).
inline constexpr std::uint64_t kPackingSeedStride = 7919;

LabDataset mean_over_packings(const std::vector<LabDataset>& packings);

}  // namespace triax::diagnose
