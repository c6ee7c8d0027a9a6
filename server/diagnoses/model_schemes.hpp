#pragma once
// The schemes of a finished diagnosis's final model: what "run with these parameters" runs,
// so that a run reproduces the model the report calibrated, not the user's scheme with new
// numbers. The diagnosis's model is not the scheme diagnosed: DemForwardModel grows the
// packing loose, caps its grains, drops the membrane for grain pressure, takes the catalog's
// effects out and sets the fitted parameters (engine/diagnose/dem_forward_model.hpp). So
// the schemes are built by the engine's own code, never re-implemented here:
//   model   the DemForwardModel run_diagnosis built: the same scheme, lab, threads per run,
//           grain cap, packings per run and relative density (options);
//   point   the report's final `parameters` (SI) by name (diagnose::final_model_point,
//           engine/diagnose/final_model.hpp): model.base_parameters() in their order, then
//           each physical effect of `effects` with model.effect_parameters(e); an effect
//           whose parameters are all at an "off" lower bound is left out, as the
//           diagnosis's runs leave it out (ModelEvaluator::physical_point);
//   schemes model.engine_runs(point): one per lab condition (confining pressure), with the
//           lab's shear end (2 % past its last reading, no softening stop) and its creep
//           stages; a condition the diagnosis ran to the end of shear only has no creep
//           stages, so a run stops where the diagnosis's stopped;
//   test artefacts  scheme_for leaves them out (the diagnosis applies them to the curves);
//           the run's protocol applies them as the report fitted them
//           (diagnose::apply_fitted_artefacts):
//             seating_strain s [-]       -> effects.seating_error, seating_displacement =
//                                           s x specimen height (strain + s at the platen);
//             membrane_stiffness K_m [Pa] -> effects.membrane_compliance, membrane modulus
//                                           E_m = K_m D / (4 t_m) with the scheme's
//                                           membrane thickness t_m, so that the protocol's
//                                           4 E_m t_m eps_a / D adds K_m eps_a to q;
//           every artefact whose parameter is in `parameters` (also one kept as a
//           correction below the naming threshold: the report's curves include it);
//   seed    options.seed: the packing the calibration's curves came from (with
//           packings_per_run > 1 the report's curves are the mean over packings, a run is
//           the first of them).
// One scheme per condition because the conditions differ in more than sigma3 (their shear
// end and creep stages come from the lab's curves at that pressure); the user picks the
// pressure on the page.
#include <nlohmann/json.hpp>

#include "engine/diagnose/diagnosis.hpp"
#include "engine/diagnose/lab_data.hpp"
#include "engine/protocol/test_scheme.hpp"

namespace triax::service {

// [{"confining_kPa": sigma3, "scheme": {...}}], one per lab condition in the model's order
// (the order the lab's pressures first appear), each scheme as io::scheme_to_json writes it
// (lab units, every field present) and named "<scheme name> (calibrated, <sigma3> kPa)":
// each passes io::scheme_from_json, so it can be POSTed to /runs as it is. Throws
// std::invalid_argument when the report's parameters do not fit the model (a missing or
// unknown name), or the scheme the engine builds does not validate.
nlohmann::json model_schemes_json(const protocol::TestScheme& scheme, const diagnose::LabDataset& lab,
                                  const diagnose::DiagnoseOptions& options, const diagnose::DiagnosisReport& report);

}  // namespace triax::service
