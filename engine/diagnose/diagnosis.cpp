// Public entry points of the diagnosis (diagnosis.hpp); the steps are DiagnosisDriver's.
#include "engine/diagnose/diagnosis.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "engine/diagnose/diagnosis_driver.hpp"
#include "engine/diagnose/simulation_batch.hpp"

namespace triax::diagnose {

namespace {

void check_options(const DiagnoseOptions& o) {
    if (o.budget_runs < 4) throw std::invalid_argument("budget_runs must be at least 4, got " + std::to_string(o.budget_runs));
    if (o.refine_runs < 1) throw std::invalid_argument("refine_runs must be at least 1");
    if (o.max_effects < 1) throw std::invalid_argument("max_effects must be at least 1");
    if (o.noise_seeds < 1) throw std::invalid_argument("noise_seeds must be at least 1");
    if (o.packings_per_run < 1 || o.packings_per_run > 16)
        throw std::invalid_argument("packings_per_run must be 1..16, got " + std::to_string(o.packings_per_run));
    if (o.relative_density && !(*o.relative_density >= 0.0 && *o.relative_density <= 1.0))
        throw std::invalid_argument("relative_density must be 0..1, got " + std::to_string(*o.relative_density));
}

// A driver with a no-op observer only to read its plan; no run is made.
class Silent final : public DiagnoseObserver {};

}  // namespace

std::vector<CandidateResult> rank_effects(const LabDataset& lab, const ForwardModel& model,
                                          const std::vector<double>& base_values, const DiagnoseOptions& options,
                                          DiagnoseObserver& observer) {
    ThreadSimulationBatch batch(options.concurrency);
    DiagnosisDriver driver(lab, model, options, observer, batch);
    return driver.rank_at(base_values);
}

DiagnosisReport run_diagnosis(const LabDataset& lab, const ForwardModel& model, const DiagnoseOptions& options,
                              DiagnoseObserver& observer, SimulationBatch& batch) {
    check_options(options);
    DiagnosisDriver driver(lab, model, options, observer, batch);
    return driver.run();
}

DiagnosisReport run_diagnosis(const LabDataset& lab, const ForwardModel& model, const DiagnoseOptions& options,
                              DiagnoseObserver& observer) {
    ThreadSimulationBatch batch(options.concurrency);
    return run_diagnosis(lab, model, options, observer, batch);
}

DiagnosisPlan plan_diagnosis(const LabDataset& lab, const ForwardModel& model, const DiagnoseOptions& options) {
    check_options(options);
    ThreadSimulationBatch batch(1);
    Silent silent;
    DiagnosisDriver driver(lab, model, options, silent, batch);
    DiagnosisPlan p;
    p.model_runs = driver.planned_runs();
    const int k = static_cast<int>(model.base_parameters().size());
    p.model_runs_low =
        options.budget_runs + std::max(0, options.noise_seeds - 1) + (options.finite_difference_uncertainty ? k : 0);
    const int steps = std::max(1, options.max_effects);
    const int weighing = driver.weighing_runs();  // a DEM creep set's kinds scatter 10x apart: it is spent
    p.model_runs_expected =
        p.model_runs_low + weighing + (std::max(0, p.model_runs - p.model_runs_low - weighing) + steps - 1) / steps;
    std::vector<double> pressures;
    for (const auto& c : lab.curves)
        if (std::none_of(pressures.begin(), pressures.end(),
                         [&](double s) { return same_confining(c.confining_pa, s); }))
            pressures.push_back(c.confining_pa);
    p.engine_runs_per_model_run = std::max<int>(1, static_cast<int>(pressures.size()));
    return p;
}

}  // namespace triax::diagnose
