#pragma once
// The reduced DEM specimen of the diagnosis checks: 50 x 100 mm, radius ratio 3 (about 200
// grains at r_min 2.5 mm, 400 at 2.0 mm), unbreakable grains (the scheme default), sheared
// to max_strain. One definition for the tests (tests/diagnose) and the bench that measures
// its noise and faithfulness (bench/diagnose_dem_noise.cpp), so both run the same specimen.
#include <cstdint>

#include "engine/protocol/test_scheme.hpp"

namespace triax::testing {

inline protocol::TestScheme reduced_scheme(double r_min_m, double max_strain, std::uint64_t seed) {
    protocol::TestScheme s;
    s.name = "reduced";
    s.specimen.diameter_m = 0.05;
    s.specimen.height_m = 0.1;
    s.gradation.r_min_m = r_min_m;
    s.gradation.radius_ratio = 3.0;
    s.loading.max_axial_strain = max_strain;
    s.seed = seed;
    return s;
}

}  // namespace triax::testing
