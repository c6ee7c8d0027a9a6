#pragma once
// DiagnosisDriver: the steps of docs/diagnosis.md on one dataset and one forward model.
//   1. calibrate_base       base parameters, test artefacts profiled (they cost no run)
//   2. measure_noise_floor  the calibrated base on other packings; the lab's reading noise
//      weigh_kinds          kinds of test far apart in scatter: weighted, base refined, floor again
//   3. add_effects          stepwise: signatures, candidate fits, selection by BIC and gain
//   4. settle_artefacts     backward pass over seating / membrane
//   5. report               errors before/after, outcome, what was held fixed or not tested
// Candidate search (signatures, line search, candidate fits) is in candidate_search.cpp.
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "engine/diagnose/calibration.hpp"
#include "engine/diagnose/diagnosis.hpp"
#include "engine/diagnose/model_evaluator.hpp"

namespace triax::diagnose {

struct Fit {
    Variant variant;
    std::vector<ParameterSpec> specs;
    CalibrationResult cal;
    double bic = 0.0;
};

class DiagnosisDriver {
public:
    DiagnosisDriver(const LabDataset& lab, const ForwardModel& model, const DiagnoseOptions& opt, DiagnoseObserver& obs,
                    SimulationBatch& batch);

    DiagnosisReport run();
    std::vector<CandidateResult> rank_at(const std::vector<double>& base_values);
    int planned_runs() const { return planned_runs_; }
    // Of them, the kinds' weighing (weigh_kinds): a refinement and a second noise floor, on
    // data with shear curves and creep stages.
    int weighing_runs() const { return weighing_runs_; }

private:
    // The steps.
    Fit calibrate_base();
    void measure_noise_floor(const Fit& base);
    Fit weigh_kinds(const Fit& base);
    Fit add_effects(Fit current, Fit& base_source);
    Fit settle_artefacts(Fit current);
    void report(const Fit& final_fit, const Fit& base_source);

    // Tools shared by the steps.
    std::vector<std::vector<double>> evaluate(const Variant& v, std::vector<UnitPoint>& batch, bool polish = true);
    Fit fit(const Variant& v, const UnitPoint& start, int design_runs, int refine_runs, bool axial,
            const CalibrationResult* history = nullptr, std::vector<UnitPoint> extra_design = {}, int local_starts = 1);
    Fit refit_free(const Variant& v, const Fit& source);
    void finite_difference_jacobian(Fit& f, bool artefacts_only = false);
    std::vector<FittedParameter> parameters_of(const Fit& f, double n_eff) const;
    double nrmse_of(double rss) const;
    void report_progress();

    // Candidate search (candidate_search.cpp).
    double score_signature(const Fit& current, const std::vector<double>& with_effect) const;
    std::vector<UnitPoint> signature_points(const UnitPoint& current, Effect e) const;
    CandidateResult signature_of(const Fit& current, Effect e, UnitPoint& best_point);
    std::vector<UnitPoint> line_search_probes(const Variant& v, const UnitPoint& start, const std::vector<UnitPoint>& probes,
                                              bool with_prior_line);
    Fit fit_candidate(const Fit& same, Effect e, const UnitPoint* signature_start);
    bool barely_on(const Fit& f) const;
    // Pooled NRMSE of the variant at the fit's point on each of the noise floor's packings
    // (a failed run counts as every reading unreached).
    std::vector<double> nrmse_on_other_packings(const Fit& f);
    int select(Fit& same, std::vector<Fit>& fits, std::vector<CandidateResult>& cands, int step);

    const DiagnoseOptions& opt_;
    DiagnoseObserver& obs_;
    ModelEvaluator eval_;
    DiagnosisReport rep_;
    // Per selection step: BIC of each fitted candidate and of the step's winner (runners-up).
    std::vector<std::vector<std::pair<std::string, double>>> step_bics_;
    std::vector<double> step_winner_bic_;
    int planned_runs_ = 1;
    int weighing_runs_ = 0;
    std::string stage_ = "calibration";
};

}  // namespace triax::diagnose
