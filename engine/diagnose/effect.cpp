// Names, signatures and artefact parameters of the effect catalog (see effect.hpp).
#include "engine/diagnose/effect.hpp"

namespace triax::diagnose {

std::string_view effect_name(Effect e) {
    switch (e) {
        case Effect::RollingResistance: return "rolling_resistance";
        case Effect::BondDegradation: return "bond_degradation";
        case Effect::ContactCreepViscosity: return "contact_creep_viscosity";
        case Effect::MoistureBonding: return "moisture_bonding";
        case Effect::SeatingError: return "seating_error";
        case Effect::MembraneCompliance: return "membrane_compliance";
    }
    return "unknown";
}

std::optional<Effect> effect_from_name(std::string_view name) {
    for (Effect e : kAllEffects)
        if (effect_name(e) == name) return e;
    return std::nullopt;
}

std::string_view effect_signature(Effect e) {
    switch (e) {
        case Effect::RollingResistance:
            return "model peak deviator too low and dilation too small (residual negative around "
                   "the peak and in the dilation phase), more so at low confining pressure";
        case Effect::BondDegradation:
            return "model deviator too high at high confining pressure and contraction missing "
                   "there, both growing with axial strain (grains crushing at the contacts); "
                   "little change at low confining pressure; creep too small at high stress level";
        case Effect::ContactCreepViscosity:
            return "creep curves of the wrong shape: log-time slope and primary/steady share wrong, "
                   "growing with stress level; shear curves barely affected";
        case Effect::MoistureBonding:
            return "constant deviator offset (apparent cohesion) that matters most at low "
                   "confining pressure, with a stiffer start";
        case Effect::SeatingError:
            return "measured axial strain offset at the start of loading: soft initial branch, "
                   "first creep stage's instant deformation too large, later curves shifted";
        case Effect::MembraneCompliance:
            return "deviator residual growing linearly with axial strain, the same in kPa at every "
                   "confining pressure (the membrane's hoop tension)";
    }
    return "";
}

std::vector<ParameterSpec> artefact_parameters(Effect e) {
    switch (e) {
        // Bedding closure of 0..2 % axial strain; 0.5 % is typical for compacted coarse fill.
        case Effect::SeatingError: return {{"seating_strain", "-", 0.0, 0.02, 0.005, false}};
        // Membrane deviator per unit axial strain, 4 E_m t_m / D (ASTM D4767): a 1 mm latex
        // membrane (E_m ~ 1.4 MPa) on D = 100 mm gives ~56 kPa; thick membranes up to ~500 kPa.
        case Effect::MembraneCompliance:
            return {{"membrane_stiffness", "Pa", 0.0, 5.0e5, 1.0e5, false}};
        default: return {};
    }
}

}  // namespace triax::diagnose
