#pragma once
// A diagnosis's fitted membrane stiffness K_m (Pa, the parameter "membrane_stiffness") as
// the scheme's membrane modulus E_m = K_m D / (4 t_m) (kPa, the form's
// effects.membrane_modulus_kPa), with the scheme's membrane thickness t_m and specimen
// diameter D: the engine's relation (engine/protocol/membrane_compliance.hpp), so the page
// shows and applies the service's value instead of mapping it again.
#include "engine/protocol/test_scheme.hpp"

#include <nlohmann/json.hpp>

namespace triax::service {

// Each "membrane_stiffness" entry of the parameter array `parameters` gains
// "scheme_field" ("/effects/membrane_modulus_kPa"), "scheme_value" (E_m, kPa) and
// "scheme_std" (its std, kPa). Nothing is added when the scheme has no membrane thickness.
void add_membrane_modulus(nlohmann::json& parameters, const protocol::TestScheme& scheme);
// The same for every parameter array of a report: parameters, base_parameters and each
// candidate's parameters.
void add_membrane_modulus_to_report(nlohmann::json& report, const protocol::TestScheme& scheme);

}  // namespace triax::service
