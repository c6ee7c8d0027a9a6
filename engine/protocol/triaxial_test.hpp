#pragma once
// The whole protocol of the seed paper on one specimen: generation at the target porosity
// by radius expansion inside the membrane, isotropic consolidation to sigma3, strain-
// controlled shear to q_f (or 15 %), then multi-stage creep at q = S_k q_f in physical time.
#include "engine/protocol/run_observer.hpp"
#include "engine/protocol/test_result.hpp"
#include "engine/protocol/test_scheme.hpp"

namespace triax::protocol {

// Phases that can be run on their own (e.g. the diagnosis needs only shear for a shear
// curve). A later phase implies the earlier ones.
enum class Phase { Consolidation, Shear, Creep };

// Runs the protocol up to and including `last`. Throws InputError on a bad scheme,
// SimulationError if the DEM becomes unphysical. Never prints.
TestResult run_triaxial_test(const TestScheme& scheme, RunObserver& observer, Phase last = Phase::Creep);

// Convenience: no observer.
TestResult run_triaxial_test(const TestScheme& scheme);

}  // namespace triax::protocol
