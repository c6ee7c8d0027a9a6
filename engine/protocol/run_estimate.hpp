#pragma once
// RunEstimate: what a scheme will cost before it runs: the specimen's size
// (estimate_specimen_size), the mechanical steps of each phase of run_triaxial_test and,
// with a measured cost per particle-step, the wall time as a range.
//
// Steps per phase (engine/protocol/triaxial_test.cpp):
//   consolidation  between kConsolidationMinSteps (the servo's first check) and the cap
//                  kConsolidationMaxSteps; typical as measured (below);
//   shear          eps_max / (rate dt), rate = I* sqrt(p0 / rho_s) / d_mean (I* = 5e-4, the
//                  quasi-static inertial number) and dt = 0.5 sqrt(m(r_dt) / kn(r_mean)),
//                  r_dt = max(r_min, 0.2 r_mean) as Specimen sets it; a softening peak ends
//                  the shear earlier (low end: half);
//   creep stage k  one loading hold (500 .. 200,000 cycles) and one relaxation hold per
//                  physical-time increment (100 .. 20,000 cycles; creep::creep_time_increments
//                  gives their number); typical cycles per hold measured.
// Minutes = steps x (grains + membrane particles) x seconds per particle-step / 60: the
// typical steps at the low and high cost give the range, the step caps the worst case.
#include "engine/protocol/specimen_budget.hpp"
#include "engine/protocol/test_scheme.hpp"

#include <string>
#include <vector>

namespace triax::protocol {

struct PhaseSteps {
    long long low = 0, typical = 0, high = 0;
};

struct RunEstimate {
    SpecimenBudget size{};
    double time_step_s = 0.0;         // the specimen's mechanical time step
    double grain_mean_radius_m = 0.0; // after the max_particles scaling
    double grain_max_radius_m = 0.0;
    double membrane_radius_m = 0.0;   // the radius Specimen gives the membrane spheres
    PhaseSteps consolidation, shear, creep, total;
    int creep_increments = 0;         // physical-time increments over all stages
    // The typical steps on a quiet machine (low), between, and on a loaded one (high); cap:
    // every hold and the consolidation at their cycle caps on a loaded machine.
    double minutes_low = 0.0, minutes_typical = 0.0, minutes_high = 0.0, minutes_cap = 0.0;
    // What a lab engineer should know before Submit (slow, coarse, at a cap); the checks
    // that refuse a scheme are TestScheme::validate's.
    std::vector<std::string> warnings;
};

// Seconds of wall time per particle per mechanical step on one thread: low = the engine
// benchmark's CPU cost (docs/engine.md: 0.15-0.16 CPU-us per particle-step for 2k-32k
// particles), high = a small specimen on this shared machine under load (the browser test's
// 236-particle scheme: 62.8 s wall for 323,350 steps at load average 12, 0.82 us).
inline constexpr double kSecondsPerParticleStepLow = 0.15e-6;
inline constexpr double kSecondsPerParticleStepHigh = 0.8e-6;
// Two threads: 1.72 x one (docs/engine.md, engine_bench).
inline constexpr double kTwoThreadSpeedup = 1.72;

// Consolidation ends when the stress and the unbalanced force meet their criteria: group B
// (2,687 grains) took 11,550 steps (docs/protocol.md), the browser test's 46 grains 263,350
// (few grains rarely meet the 1e-3 unbalanced-force ratio). Typical: the first for 1,000
// grains and more, the second below 300, log-interpolated between.
inline constexpr long long kConsolidationMinSteps = 2'000;
inline constexpr long long kConsolidationLargeSpecimenSteps = 12'000;
inline constexpr long long kConsolidationSmallSpecimenSteps = 260'000;
inline constexpr long long kConsolidationMaxSteps = 400'000;
// Creep holds (triaxial_test.cpp: hold(..., 500, 200000) at the load step, hold(..., 100,
// 20000) per increment). Typical per increment: group B's creep stages took about 530,000
// steps over its ~360 increments (634,050 steps in all, docs/protocol.md).
inline constexpr long long kLoadingHoldMin = 500, kLoadingHoldTypical = 5'000, kLoadingHoldMax = 200'000;
inline constexpr long long kIncrementHoldMin = 100, kIncrementHoldTypical = 1'400, kIncrementHoldMax = 20'000;

// Throws InputError (naming the field) for a scheme validate() refuses.
RunEstimate estimate_run(const TestScheme& s);

// Throws InputError naming micro.membrane_particle_radius_m when a chosen membrane sphere
// radius is too small for the specimen's smallest grain (after the max_particles scaling):
// such a lattice lets grains out in consolidation (boundary::kMaxGrainToMembraneRadius).
// Part of TestScheme::validate.
void check_membrane_holds_grains(const TestScheme& s);

}  // namespace triax::protocol
