#pragma once
// Multi-stage creep in physical time on a consolidated specimen (the paper's graded
// loading, "Scheme of Creep Test"). Each stage k:
//   1. the contacts' shear forces become the reference of their renewal
//      (RateStateCreep::begin_stage), then the loading step holds sigma1 = sigma3 + q_k (CreepHold): the instant reading;
//   2. the stage's physical time advances in scheduled increments
//      (creep::creep_time_increments), each split while it would relax more than
//      creep.max_relaxation_per_increment of the contact shear force at once; after each
//      piece the creep law advances the contacts by dt and a hold relaxes the specimen at
//      the held stress: the reading at the increment's end;
//   3. the stage ends at its duration, or at creep rupture (the platen runs away beyond the
//      shear test's range, or a collapse within an increment, creep_regime.hpp);
//   4. its curve is coordinate-translated (Boltzmann superposition) and classified.
// The DEM cycles of the holds carry no physical time (docs/creep.md, "How DEM cycles map
// to physical time"). Measurement spheres (porosity, coordination, displacement, rotation
// rate in physical time) are sampled at the loading step and every fourth increment.
#include <vector>

#include "engine/creep/rate_state_creep.hpp"
#include "engine/measure/measurement_sphere.hpp"
#include "engine/protocol/creep_hold.hpp"
#include "engine/protocol/run_context.hpp"
#include "engine/protocol/specimen.hpp"

namespace triax::protocol {

class MultiStageCreep {
public:
    // q_failure_pa and max_axial_strain: the companion shear test's q_f and strain range.
    MultiStageCreep(Specimen& sp, const PlatenServo& servo, double q_failure_pa, RunContext& run);

    // Stage k (0-based) at deviator q_target_pa for the scheme's k-th duration.
    CreepStageResult run_stage(int k, double q_target_pa);

private:
    void sample_spheres(double t);

    Specimen& sp_;
    World& w_;
    RunContext& run_;
    const double sigma3_, q_failure_, eps_max_;
    creep::RateStateCreep law_;
    CreepHold holder_;
    // Grain rotation accumulated over the relaxation cycles (rad): divided by the physical
    // time between samples it is the rotation rate in physical time (the DEM spin at an
    // equilibrium snapshot is only residual noise).
    std::vector<Vec3> rotation_;
    std::vector<MeasurementSphere> spheres_;
    double hc_, z_top0_;         // reference height and platen position of the creep test
    double t_total_ = 0.0;       // physical time since the creep test started
    double last_sample_t_ = 0.0;
};

// The scheme's creep law with the diagnosis effects applied: the creep effect scales the
// law's critical slip D_c and the corrosion rate (off: no creep), accelerated corrosion scales the bonds' corrosion rate.
creep::RateStateParams effective_creep_law(const TestScheme& scheme);

}  // namespace triax::protocol
