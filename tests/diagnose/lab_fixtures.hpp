#pragma once
// Fixtures shared by the diagnosis tests: lab curves built by hand (shear, creep), the
// conditions-only datasets a DemForwardModel is built on (a curve per confining pressure
// whose readings only fix the pressure and the strain range), and the reduced DEM
// specimen of the CI cases (tests/support/reduced_specimen.hpp).
#include <cstdint>
#include <vector>

#include "engine/diagnose/lab_data.hpp"
#include "engine/protocol/test_scheme.hpp"
#include "tests/support/reduced_specimen.hpp"

namespace triax::diagnose::testing {

inline LabCurve shear_curve(double confining_pa, std::vector<double> axial_strain, std::vector<double> deviator_pa,
                            std::vector<double> volumetric_strain = {}) {
    LabCurve c;
    c.kind = CurveKind::Shear;
    c.confining_pa = confining_pa;
    c.axial_strain = std::move(axial_strain);
    c.deviator_pa = std::move(deviator_pa);
    c.volumetric_strain = std::move(volumetric_strain);
    return c;
}

inline LabCurve creep_curve(int stage, double confining_pa, std::vector<double> time_s, std::vector<double> axial_strain,
                            double stress_level = 0.0, std::vector<double> axial_deformation_m = {}) {
    LabCurve c;
    c.kind = CurveKind::Creep;
    c.stage = stage;
    c.confining_pa = confining_pa;
    c.stress_level = stress_level;
    c.time_s = std::move(time_s);
    c.axial_strain = std::move(axial_strain);
    c.axial_deformation_m = std::move(axial_deformation_m);
    return c;
}

// Shear-only conditions: one placeholder curve to max_strain per confining pressure.
inline LabDataset shear_conditions(const std::vector<double>& confining_pa, double max_strain = 0.02) {
    LabDataset lab;
    for (double s3 : confining_pa) lab.curves.push_back(shear_curve(s3, {0.0, 0.5 * max_strain, max_strain}, {0.0, 1e5, 2e5}));
    return lab;
}

// The reduced DEM specimen of the CI cases (shared with bench/diagnose_dem_noise.cpp).
using triax::testing::reduced_scheme;

}  // namespace triax::diagnose::testing
