#pragma once
// The product's forward model: the DEM triaxial protocol (engine/protocol) run at the lab
// dataset's conditions. One simulate() = one run of run_triaxial_test per confining
// pressure in the lab data (shear only if the lab has no creep curve at that pressure),
// with creep stress levels and stage durations taken from the lab's creep curves. Every
// shear runs to the lab's last reading at that pressure (2 % beyond it) with no softening
// stop, so the model's curve covers the lab's range whatever the material does.
//
// The base model is the scheme with every catalog effect taken out, so that each can be
// tested against it (a base that already resists rolling through its bonds' cement neck
// cannot be told it lacks rolling resistance):
//   rolling resistance off (micro.rolling_friction 0, the bonds' neck
//     micro.bond_rolling_friction 0), grain crushing off, extra bond damage off, the creep
//     law off (the creep effect switches it on), seating and membrane artefacts off.
// Base parameters (calibrated in every model), over ranges wide enough for real fills:
//   contact normal modulus E_n (log, 0.1x..10x the scheme's; E_s keeps the scheme's ratio),
//   particle friction mu (0.05..1),
//   contact bond strength (normal = shear, Pa, linear from 0 = cohesionless to
//     max(3x the scheme's, 300 kPa)); its nominal is 0 unless the lab's peak strengths
//     carry a cohesion intercept (lab_macro.hpp),
//   compaction friction ratio (0..1): the friction the grains are consolidated at, as a
//     multiple of theirs (0: frictionless, the densest packing, an early peak and dilation;
//     1: their own, the loosest, contraction and hardening to late strains), on a packing
//     grown loose (porosity kDiagnosisGenerationPorosity); held at the lab's relative
//     density instead when the lab states one (compaction_friction_for).
// Everything else the scheme sets is held at the scheme's value and listed by held_fixed().
// Effects and their parameters:
//   rolling_resistance      -> rolling_friction mu_r (0..0.5, 0 = off)
//   bond_degradation        -> grain crushing: crushability x = 0.6 MPa / sigma0 (0..2, 0 =
//                              unbreakable); with creep curves of a bonded specimen also extra
//                              bond damage e (0..9): effects.accelerated_bond_corrosion,
//                              bond_corrosion_scale 1 + e
//   contact_creep_viscosity -> the creep law on with slip-hardening length s_h (0..8x the
//                              scheme's, 0 = no creep); offered only with creep curves
//   moisture_bonding        -> not offered: the base calibrates the bond strength from 0
// Every run uses the given seed (common random numbers: the same packings for every parameter
// set, so differences between runs are the parameters', not the packing's); a run is the
// mean of `packings` packings (packing_ensemble.hpp).
#include "engine/diagnose/forward_model.hpp"
#include "engine/protocol/test_scheme.hpp"
#include "engine/protocol/triaxial_test.hpp"

namespace triax::diagnose {

class DiagnoseObserver;
struct DiagnoseOptions;

// Grain crushability x = kCrushabilityReferencePa / crushing strength: x = 1 is a grain of
// 0.6 MPa, x = kCrushabilityMax (0.3 MPa) the weakest offered.
inline constexpr double kCrushabilityReferencePa = 0.6e6;
inline constexpr double kCrushabilityMax = 2.0;
// The creep effect's rate sensitivity a spans 0 (off) to kCreepDirectEffectMax; an "on"
// value is at least kCreepDirectEffectMin. Its nominal is read off the lab's creep per
// decade at its highest stress level through the calibration specimen's measured response,
// creep per decade ~ kCreepPerDecadeAtRef (a / kCreepRefA)^kCreepPerDecadeExponent
// (bench/README.md, "Rate-and-state contact creep": S 0.8, one-day stages, median over the
// seeds without a burst or rupture: 7.3e-5 strain per decade at a 0.03, 1.00e-4 at 0.06,
// 1.38e-4 at 0.1; exponent ln(1.38 / 0.73) / ln(0.1 / 0.03) = 0.53). The creep per decade
// grows slowly with a because each contact's slip per e-fold of time is bounded by
// a Fn / ks (docs/creep.md section 9), and seeds scatter by about 2x around the law: the
// seed is a start for the fit, not an estimate.
inline constexpr double kCreepDirectEffectMin = 0.002;
inline constexpr double kCreepDirectEffectMax = 0.08;
inline constexpr double kCreepRefA = 0.03;
inline constexpr double kCreepPerDecadeAtRef = 7.3e-5;  // strain per decade at a = kCreepRefA
inline constexpr double kCreepPerDecadeExponent = 0.53;
// The nominal a for a lab creep of strain_per_decade at its highest stress level.
double creep_direct_effect_for(double strain_per_decade);
// The base grows its packing loose, so that the compaction friction spans dense to loose
// (bench/base_reach porosity=0.45 compaction=0,1: consolidated porosity 0.370-0.386 and
// 0.400-0.412; from 0.35 the loose end is not reached).
inline constexpr double kDiagnosisGenerationPorosity = 0.45;
// A lab specimen's relative density D_r (0 = loosest, 1 = densest) as the model's
// compaction friction ratio, 1 - D_r: the same place between the model's loosest
// (consolidated at the grains' friction) and densest (frictionless) packings. A convention
// between two materials' scales (a crushed-rock fill's e_min/e_max and a sphere packing's),
// not an identity; the lab's stated density is held rather than calibrated.
inline constexpr double compaction_friction_for(double relative_density) { return 1.0 - relative_density; }

class DemForwardModel final : public ForwardModel {
public:
    // threads: OpenMP threads per run; max_particles > 0 overrides the scheme's cap.
    // `cancel` (may be null) is polled inside every DEM run, from the worker threads, so a
    // cancelled diagnosis does not wait for a long run to finish.
    // `packings` >= 1: packings (seeds) whose mean curves are one model run (packing_ensemble.hpp).
    // `relative_density` (0..1): the lab specimen's, when the lab states it; the compaction
    // friction is then held at compaction_friction_for(it) instead of calibrated.
    DemForwardModel(const protocol::TestScheme& base, const LabDataset& lab, int threads, int max_particles,
                    const DiagnoseObserver* cancel = nullptr, int packings = 1,
                    std::optional<double> relative_density = std::nullopt);
    // The model a diagnosis with these options runs (run_diagnosis): threads_per_run,
    // max_particles, packings_per_run and relative_density taken from them. One place for
    // every caller that must build the same model (the plan, the stored model schemes, the
    // MPI command line).
    DemForwardModel(const protocol::TestScheme& base, const LabDataset& lab, const DiagnoseOptions& options,
                    const DiagnoseObserver* cancel = nullptr);

    std::vector<ParameterSpec> base_parameters() const override;
    std::vector<ParameterSpec> effect_parameters(Effect e) const override;
    bool includes(Effect e) const override;
    std::string not_offered_reason(Effect e) const override;
    std::vector<HeldParameter> held_fixed() const override;
    // The mean over the model's packings: seed, seed + kPackingSeedStride, ...
    LabDataset simulate(const ModelPoint& point, std::uint64_t seed) const override;
    int packings() const { return packings_; }
    double specimen_height_m() const override { return base_.specimen.height_m; }

    // The scheme a model point runs at one confining pressure (exposed for tests and for
    // storing the calibrated scheme).
    protocol::TestScheme scheme_for(const ModelPoint& point, double confining_pa) const;

    // The engine runs of one model run at `point` (one packing, seed not set): per lab
    // condition the scheme as simulate() runs it (the lab's shear end and creep stages) and
    // the protocol phase it runs to (Shear where the lab has no creep curve there; the
    // scheme's creep stages are then not run). A cost estimate reads these.
    struct EngineRun {
        protocol::TestScheme scheme;
        protocol::Phase last_phase = protocol::Phase::Shear;
        // The scheme on its own, as this run runs it: a shear-only run's creep stages are
        // cleared (they are not run), so a cost estimate or a stored scheme does not count
        // them.
        protocol::TestScheme standalone_scheme() const {
            protocol::TestScheme s = scheme;
            if (last_phase != protocol::Phase::Creep) {
                s.loading.stress_levels.clear();
                s.loading.stage_durations_s.clear();
            }
            return s;
        }
    };
    std::vector<EngineRun> engine_runs(const ModelPoint& point) const;

private:
    struct Condition {
        double confining_pa = 0.0;
        bool creep = false;
        std::vector<double> stress_levels;
        std::vector<double> durations_s;
        double max_axial_strain = 0.0;  // shear to 2 % past the lab's last reading
        bool lab_shear = false;         // the lab has a shear curve at this pressure
    };
    protocol::TestScheme scheme_;  // as given
    protocol::TestScheme base_;    // the scheme without the catalog's effects
    const DiagnoseObserver* cancel_ = nullptr;
    int packings_ = 1;
    std::optional<double> relative_density_;  // the lab's D_r: compaction friction held, not calibrated
    double compaction_nominal_ = 1.0;          // the calibration's start (from the lab's curves)
    LabDataset simulate_packing(const ModelPoint& point, std::uint64_t seed) const;
    std::vector<Condition> conditions_;
    bool creep_in_lab_ = false;
    double bond_strength_max_pa_ = 0.0;
    double bond_strength_nominal_pa_ = 0.0;
    // The bond strength is a base parameter only when the lab shows cohesion (its peak
    // Mohr-Coulomb envelope has an intercept above 5 % of q); otherwise it is held at 0.
    bool bonds_calibrated_ = false;
    double creep_seed_a_ = kCreepRefA;  // the creep effect's nominal a (creep_direct_effect_for)
    double lab_cohesion_pa_ = 0.0;  // the lab's peak envelope intercept c'
    std::string lab_cohesion_text() const;  // "c' = 6 kPa", for the report's reasons
};

}  // namespace triax::diagnose
