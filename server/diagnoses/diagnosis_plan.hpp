#pragma once
// What a diagnosis will cost before it starts: the answer of POST
// /datasets/{id}/diagnosis-plan and the "plan" of the diagnose 202 (docs/api.md).
//   model runs  at most and low: the engine's own plan (diagnose::plan_diagnosis,
//               DiagnosisPlan::model_runs and model_runs_low).
//   minutes     protocol::estimate_run of each engine run of one model run at the DEM
//               model's nominal point: one per lab condition (confining pressure), as
//               DemForwardModel::engine_runs gives them (the lab's shear end and creep
//               stages), times packings_per_run; the whole diagnosis is
//               ceil(model runs / concurrency) model runs one after another:
//               low = ceil(low runs / c) x the quiet-machine minutes,
//               expected = ceil(expected runs / c) x the typical minutes,
//               high = ceil(runs at most / c) x the loaded-machine minutes.
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/diagnose/diagnosis.hpp"
#include "engine/diagnose/lab_data.hpp"
#include "engine/protocol/test_scheme.hpp"

namespace triax::service {

// Wall minutes as protocol::RunEstimate states them: the typical steps on a quiet machine
// (low), between (typical) and on a loaded one (high).
struct MinutesRange {
    double low = 0.0, typical = 0.0, high = 0.0;
};

// One lab condition: one engine run per model run and packing.
struct PlannedCondition {
    double confining_pa = 0.0;
    int creep_stages = 0;           // creep stages after the shear (0: the shear alone)
    double max_axial_strain = 0.0;  // [-] where the shear ends
    MinutesRange minutes;           // one engine run
};

struct DiagnosisCost {
    diagnose::DiagnosisPlan plan;  // model runs at most and low, engine runs per model run
    long long grains = 0;          // soil grains of one engine run (the calibration specimen)
    std::vector<PlannedCondition> conditions;
    MinutesRange minutes_per_model_run;            // packings_per_run x the sum over conditions
    // The whole diagnosis at options.concurrency: low, expected (model_runs_expected at the
    // typical minutes) and high.
    double minutes_low = 0.0, minutes_expected = 0.0, minutes_high = 0.0;
};

// Starts nothing. Throws std::invalid_argument (the engine's message) when the dataset has
// no curve a diagnosis can use or an engine run's scheme cannot be estimated: the
// diagnosis itself would fail the same way.
DiagnosisCost plan_diagnosis_cost(const diagnose::LabDataset& lab, const protocol::TestScheme& scheme,
                                  const diagnose::DiagnoseOptions& options);

// Lab units at the edge: kPa, strain in %, minutes. `options` as GET /diagnoses/{id}
// carries them (io::diagnose_options_to_json).
nlohmann::json diagnosis_cost_to_json(const DiagnosisCost& cost, const diagnose::DiagnoseOptions& options);

}  // namespace triax::service
