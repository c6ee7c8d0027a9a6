#pragma once
// A finished diagnosis's final model as runs: the point of the model space its report
// names, and the test artefacts it fitted as a scheme's protocol applies them. What "run
// with these parameters" runs (server/diagnoses/model_schemes.hpp); no I/O.
#include <vector>

#include "engine/diagnose/diagnosis.hpp"
#include "engine/diagnose/forward_model.hpp"
#include "engine/protocol/test_scheme.hpp"

namespace triax::diagnose {

// The report's final `parameters` (SI) by name as the point `model` runs: its
// base_parameters() in their order, then each physical effect of report.effects with
// model.effect_parameters(e); an effect whose parameters are all at an "off" lower bound is
// left out, as the diagnosis's runs leave it out (ModelEvaluator::physical_point); test
// artefacts are not part of the point. Effects sorted. Throws std::invalid_argument for a
// parameter the report lacks, an unknown effect name or one the model cannot represent.
ModelPoint final_model_point(const ForwardModel& model, const DiagnosisReport& report);

// The fitted test artefacts switched on in a scheme, for its protocol to apply:
//   seating_strain s [-]        -> effects.seating_error, seating_displacement = s x height;
//   membrane_stiffness K_m [Pa] -> effects.membrane_compliance, membrane modulus from K_m
//                                  with the scheme's thickness and diameter
//                                  (protocol/membrane_compliance.hpp).
// Only a parameter present and > 0 switches its artefact on. Throws std::invalid_argument
// when membrane compliance is fitted and the scheme's membrane thickness is not > 0.
void apply_fitted_artefacts(protocol::TestScheme& scheme, const std::vector<FittedParameter>& parameters);

}  // namespace triax::diagnose
