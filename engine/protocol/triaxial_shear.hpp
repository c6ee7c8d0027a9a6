#pragma once
// Strain-controlled (drained) triaxial shear of a consolidated specimen: the top platen
// moves at a constant axial strain rate, the membrane holds sigma3, until the axial strain
// reaches loading.max_axial_strain or the specimen softens (a clear peak, then q 20 %
// below it past 2 % strain). The rate is the quasi-static one of the density-scaled
// grains: inertial number I = eps_dot d sqrt(rho / p) = 5e-4 at p = sigma3 (GDR MiDi
// 2004: quasi-static below about 1e-3), whatever the lab rate. Readings every 0.2 % of
// axial strain: q (with the seating and membrane-compliance artefacts when switched on),
// volumetric strain, inertial number; result.shear, max_inertial_number,
// inertial_density_kg_m3 and the shear energy samples.
#include "engine/protocol/run_context.hpp"
#include "engine/protocol/specimen.hpp"

namespace triax::protocol {

struct ShearOutcome {
    double q_failure_pa = 0.0;           // peak deviator q_f
    double axial_strain_at_failure = 0.0;
};

ShearOutcome shear_to_failure(Specimen& sp, RunContext& run);

}  // namespace triax::protocol
