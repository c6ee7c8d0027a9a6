#pragma once
// The product's forward model: the DEM triaxial protocol (engine/protocol) run at the lab
// dataset's conditions. One simulate() = one run of run_triaxial_test per confining
// pressure in the lab data (shear only if the lab has no creep curve at that pressure),
// with creep stress levels and stage durations taken from the lab's creep curves.
//
// Base parameters (calibrated in every model):
//   contact normal modulus E_n (log, 0.2x..5x the scheme's; E_s keeps the scheme's ratio),
//   particle friction mu (0.1..0.7: a physical prior, see base_parameters()),
//   contact bond strength (log, x1/3..x3; normal and shear scaled together) if the
//     scheme's specimen carries bonds,
//   creep slip-rate scale A (log, 0.01x..100x) when the creep law is on and the lab
//     has creep curves (otherwise the creep curves cannot inform it).
// Effects already switched on in the scheme are part of the base model and are not
// proposed; the others map to TestEffects:
//   rolling_resistance      -> rolling_friction mu_r (0..0.5)
//   bond_degradation        -> grain crushing: crushability x = 0.6 MPa / sigma0 (0..2, 0 =
//                              unbreakable), micro.crushing_strength_pa = 0.6 MPa / x; with
//                              creep curves of a bonded specimen also extra bond damage e
//                              (0..9): effects.accelerated_bond_corrosion, bond_corrosion_scale 1 + e
//   contact_creep_viscosity -> contact_creep_viscosity, viscosity_scale (log 0.01..100)
//   moisture_bonding        -> moisture_bonding; one parameter: bond strength scale at the
//                              scheme's moisture (log 0.05..20)
// Every run uses the scheme's seed (common random numbers: the same specimen for every
// parameter set, so differences between runs are the parameters', not the packing's).
#include "engine/diagnose/forward_model.hpp"
#include "engine/protocol/test_scheme.hpp"

namespace triax::diagnose {

class DiagnoseObserver;

// Grain crushability x = kCrushabilityReferencePa / crushing strength: x = 1 is a grain of
// 0.6 MPa (the presets' grain of sessions 8-11, on which the diagnosis was calibrated),
// x = kCrushabilityMax (0.3 MPa) the weakest tried.
inline constexpr double kCrushabilityReferencePa = 0.6e6;
inline constexpr double kCrushabilityMax = 2.0;

class DemForwardModel final : public ForwardModel {
public:
    // threads: OpenMP threads per run; max_particles > 0 overrides the scheme's cap.
    // `cancel` (may be null) is polled inside every DEM run, from the worker threads, so a
    // cancelled diagnosis does not wait for a long run to finish.
    DemForwardModel(const protocol::TestScheme& base, const LabDataset& lab, int threads, int max_particles,
                    const DiagnoseObserver* cancel = nullptr);

    std::vector<ParameterSpec> base_parameters() const override;
    std::vector<ParameterSpec> effect_parameters(Effect e) const override;
    bool includes(Effect e) const override;
    LabDataset simulate(const ModelPoint& point, std::uint64_t seed) const override;

    // The scheme a model point runs at one confining pressure (exposed for tests and for
    // storing the calibrated scheme).
    protocol::TestScheme scheme_for(const ModelPoint& point, double confining_pa) const;

private:
    struct Condition {
        double confining_pa = 0.0;
        bool creep = false;
        std::vector<double> stress_levels;
        std::vector<double> durations_s;
    };
    protocol::TestScheme base_;
    const DiagnoseObserver* cancel_ = nullptr;
    std::vector<Condition> conditions_;
    bool creep_in_lab_ = false;
    bool bonded_ = false;
};

}  // namespace triax::diagnose
