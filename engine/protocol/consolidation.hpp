#pragma once
// Isotropic consolidation of a generated specimen to sigma3: both platens servo-controlled
// to sigma3 (platen_servo.hpp), the membrane at sigma3, friction on, until after at least
// 2000 cycles the axial stress is within 1 % of sigma3 and the unbalanced-force ratio is
// below loading.consolidation_tolerance (at most 400,000 cycles). Reports
// result.consolidation and the first energy sample. The bonds and crushable grains are
// not installed here: they form on the consolidated fabric (Specimen::install_soil_bonds,
// enable_crushing), which the orchestrator does next.
#include "engine/protocol/run_context.hpp"
#include "engine/protocol/specimen.hpp"

namespace triax::protocol {

void consolidate_isotropically(Specimen& sp, RunContext& run);

}  // namespace triax::protocol
