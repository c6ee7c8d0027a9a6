#pragma once
// Test artefacts as post-processing of predicted curves: what the instruments would have
// read if the specimen behaved as the model says. No engine run is needed for them.
//
// Seating (bedding) error, parameter s [-]: the platens close gaps of s (in axial strain)
// under almost no load before the specimen is loaded, so every measured axial strain of
// the shear curve is the specimen's strain plus s (the curve starts with a flat branch at
// q ~ 0), and the first creep stage's readings (measured from the start of loading)
// include s in their instant deformation. Later creep stages are zeroed at their start by
// the coordinate translation, so they do not see it.
//
// Membrane compliance, parameter K_m [Pa]: the membrane carries hoop tension, so the
// measured deviator is the soil's plus K_m * eps_a (K_m = 4 E_m t_m / D, protocol/membrane_compliance.hpp);
// the same in Pa at every confining pressure, hence relatively larger at low sigma3.
#include <vector>

#include "engine/diagnose/effect.hpp"
#include "engine/diagnose/lab_data.hpp"

namespace triax::diagnose {

// Applies one artefact in place; throws std::invalid_argument for a physical effect or a
// wrong parameter count.
void apply_test_artefact(LabDataset& predicted, Effect e, const std::vector<double>& parameters,
                         double specimen_height_m = 0.2);

}  // namespace triax::diagnose
