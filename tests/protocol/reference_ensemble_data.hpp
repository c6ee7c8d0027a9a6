#pragma once
// The stored reference ensemble of the engine's statistical contract
// (tests/support/reference_ensemble.hpp): mean and sample standard deviation of each
// quantity over packing seeds 101-124, in the order of kEnsembleQuantities. Renewed only
// by `./build/bench/reference_ensemble seeds=101-124 record=1`, with a note in the commit
// saying which change moved it and by how much (docs/engine.md, "The contract across builds").
#include "tests/support/reference_ensemble.hpp"

namespace triax::testing {

inline const EnsembleMoments kReferenceEnsemble = {
    24,
    {119.46681666666667, 138.15922083333331, 135.60705833333333, 137.08941666666666, 175.234375, -0.77431550833333318, -1.6487898083333334, -1.7597859372297886, -1.5678393435997819},
    {25.107563015859633, 25.99830523416243, 23.539790349827687, 19.254810723368685, 18.998362306565316, 0.55972439439658073, 0.62629129655886639, 0.48212375562482601, 0.52457060266428812}};

}  // namespace triax::testing
