#pragma once
// DiagnosisReport <-> JSON (the `report` of GET /diagnoses/{id}, docs/api.md) and the
// request body of POST /datasets/{id}/diagnose -> DiagnoseOptions.
//
// Lab units at the edge: a curve error on a deviator is given in kPa, on a strain in %
// ("unit" says which; NRMSE stays a fraction of the lab curve's range). Fitted model
// parameters keep their SI unit, named in "unit" (they are micro-parameters, not lab
// readings). The conversion is exact both ways, so a stored report reads back equal.
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/diagnose/diagnosis.hpp"

namespace triax::io {

// A request field at fault: `field` is a JSON pointer ("/budget_runs").
struct DiagnosisRequestError : std::invalid_argument {
    std::string field;
    DiagnosisRequestError(std::string pointer, const std::string& detail)
        : std::invalid_argument(detail), field(std::move(pointer)) {}
};

nlohmann::json diagnosis_report_to_json(const diagnose::DiagnosisReport& report);
// Throws nlohmann::json::exception or std::invalid_argument on a malformed document.
diagnose::DiagnosisReport diagnosis_report_from_json(const nlohmann::json& j);

// The `candidate` SSE event payload.
nlohmann::json candidate_to_json(const diagnose::CandidateResult& candidate);
// ... and read back (the `triax diagnose` child's candidate lines, mpi_job_launcher).
diagnose::CandidateResult candidate_from_json(const nlohmann::json& j);

// Optional fields: budget_runs (4..400), refine_runs (1..100), max_candidates (1..6),
// max_effects (1..6), concurrency (1..64), threads_per_run (1..64), max_particles
// (0..1e6, 0 = the scheme's), seed (>= 0),
// bic_threshold (>= 0), finite_difference_uncertainty (true/false: the parameters' std from
// a forward-difference Jacobian at the optimum, k extra runs per reported model, or from
// the regression over the runs already made). Unknown fields are ignored (the body also carries the scheme);
// null means all defaults.
diagnose::DiagnoseOptions diagnose_options_from_json(const nlohmann::json& body);
// Every option with the value the diagnosis uses (defaults filled in): the `options` of
// GET /diagnoses/{id}, so a report says how it was made.
nlohmann::json diagnose_options_to_json(const diagnose::DiagnoseOptions& options);

}  // namespace triax::io
