#include "server/diagnoses/diagnosis_plan.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/diagnose/dem_forward_model.hpp"
#include "engine/protocol/run_estimate.hpp"
#include "server/io/diagnosis_json.hpp"

namespace triax::service {

using nlohmann::json;

namespace {

json minutes_json(const MinutesRange& m) { return {{"low", m.low}, {"typical", m.typical}, {"high", m.high}}; }

}  // namespace

DiagnosisCost plan_diagnosis_cost(const diagnose::LabDataset& lab, const protocol::TestScheme& scheme,
                                  const diagnose::DiagnoseOptions& options) {
    const diagnose::DemForwardModel model(scheme, lab, options);
    DiagnosisCost cost;
    cost.plan = diagnose::plan_diagnosis(lab, model, options);
    diagnose::ModelPoint nominal;
    for (const auto& p : model.base_parameters()) nominal.base.push_back(p.nominal);
    MinutesRange per_packing;
    for (const auto& run : model.engine_runs(nominal)) {
        const protocol::TestScheme s = run.standalone_scheme();
        const protocol::RunEstimate e = protocol::estimate_run(s);
        cost.grains = e.size.grains;
        cost.conditions.push_back({s.loading.confining_pressure_pa, static_cast<int>(s.loading.stress_levels.size()),
                                   s.loading.max_axial_strain, {e.minutes_low, e.minutes_typical, e.minutes_high}});
        per_packing.low += e.minutes_low;
        per_packing.typical += e.minutes_typical;
        per_packing.high += e.minutes_high;
    }
    const double packings = model.packings();
    cost.minutes_per_model_run = {packings * per_packing.low, packings * per_packing.typical, packings * per_packing.high};
    // Runs at once: a batch's runs, spread over the evaluation threads.
    const int at_once = std::max(1, std::min(options.concurrency, options.batch_runs));
    const auto rounds = [&](int runs) { return std::ceil(static_cast<double>(runs) / at_once); };
    cost.minutes_low = rounds(cost.plan.model_runs_low) * cost.minutes_per_model_run.low;
    cost.minutes_expected = rounds(cost.plan.model_runs_expected) * cost.minutes_per_model_run.typical;
    cost.minutes_high = rounds(cost.plan.model_runs) * cost.minutes_per_model_run.high;
    return cost;
}

json diagnosis_cost_to_json(const DiagnosisCost& cost, const diagnose::DiagnoseOptions& options) {
    json conditions = json::array();
    for (const auto& c : cost.conditions)
        conditions.push_back({{"confining_kPa", c.confining_pa / 1e3},
                              {"creep_stages", c.creep_stages},
                              {"max_axial_strain_pct", 100.0 * c.max_axial_strain},
                              {"minutes_per_engine_run", minutes_json(c.minutes)}});
    return {{"model_runs_at_most", cost.plan.model_runs},
            {"model_runs_low", cost.plan.model_runs_low},
            {"model_runs_expected", cost.plan.model_runs_expected},
            {"engine_runs_per_model_run", cost.plan.engine_runs_per_model_run},
            {"grains", cost.grains},
            {"lab_conditions", conditions},
            {"minutes_per_model_run", minutes_json(cost.minutes_per_model_run)},
            {"minutes_estimate", {{"low", cost.minutes_low}, {"expected", cost.minutes_expected}, {"high", cost.minutes_high}}},
            {"options", io::diagnose_options_to_json(options)}};
}

}  // namespace triax::service
