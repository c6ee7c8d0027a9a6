#pragma once
// The catalog of model extensions the diagnosis can propose. Each effect has one or two
// parameters and a residual signature (what the base model gets wrong when the effect is
// present in the specimen but missing from the model); docs/diagnosis.md tabulates them.
// Physical effects need engine runs; test artefacts are post-processing of model output.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace triax::diagnose {

enum class Effect {
    RollingResistance,      // particle shape / interlocking
    BondDegradation,        // grain breakage or bond damage under high stress
    ContactCreepViscosity,  // time-dependent contact creep
    MoistureBonding,        // moisture-dependent (capillary / suction) bonding
    SeatingError,           // test artefact: bedding of platens at the start of loading
    MembraneCompliance,     // test artefact: load carried by the membrane (hoop tension)
};

inline constexpr Effect kAllEffects[] = {Effect::RollingResistance,     Effect::BondDegradation,
                                         Effect::ContactCreepViscosity, Effect::MoistureBonding,
                                         Effect::SeatingError,          Effect::MembraneCompliance};

// Test artefacts change what the instruments read, not what the soil does.
constexpr bool is_test_artefact(Effect e) {
    return e == Effect::SeatingError || e == Effect::MembraneCompliance;
}

// snake_case identifier used in reports and the REST API ("rolling_resistance", ...).
std::string_view effect_name(Effect e);
std::optional<Effect> effect_from_name(std::string_view name);
// One sentence: the residual the effect explains when it is missing from the model.
std::string_view effect_signature(Effect e);

// A model parameter: bounds of the search box and the scale the search works on.
// Log-scaled parameters (stiffnesses, viscosities) are searched uniformly in log space.
struct ParameterSpec {
    std::string name;   // e.g. "contact_normal_stiffness"
    std::string unit;   // SI unit, e.g. "N/m", "-", "Pa"
    double lower = 0.0;
    double upper = 1.0;
    double nominal = 0.5;  // used as the starting point and for signatures
    bool log_scale = false;
    // At the lower bound the effect is absent (mu_r = 0): the model is then the model
    // without it, so runs already made without the effect can seed its fit for free.
    bool lower_is_off = false;
};

// Parameters of the two test artefacts (the physical ones come from the ForwardModel).
std::vector<ParameterSpec> artefact_parameters(Effect e);

}  // namespace triax::diagnose
