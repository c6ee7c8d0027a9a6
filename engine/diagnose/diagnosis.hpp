#pragma once
// Closing the loop: calibrate the base model to lab readings, measure what a change of
// packing gives (the noise floor), split the residual by curve and phase, rank the catalog's
// effects by how well their signature matches the residual, fit the best candidates as
// augmented models and keep one only if it earns its parameters by BIC with an effective
// number of readings and gains more than the noise floor; call what remains above the
// tolerance of a right model "unexplained". Algorithm and budget: docs/diagnosis.md.
// The engine returns data; the sentence a user reads is written at the edge
// (server/io/diagnosis_verdict).
#include <cstddef>
#include <cstdint>
#include <exception>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/diagnose/effect.hpp"
#include "engine/diagnose/forward_model.hpp"
#include "engine/diagnose/lab_data.hpp"
#include "engine/diagnose/noise_floor.hpp"

namespace triax::protocol {
struct TestScheme;
}

namespace triax::diagnose {

struct DiagnoseOptions {
    // The defaults are the measured "minutes, not hours" set (docs/diagnosis.md section 5):
    // three shear curves to 15 % on the ~200-grain calibration specimen in about 5 min on
    // two cores, a 3-pressure 4-stage creep set in about half an hour.
    int budget_runs = 12;          // model evaluations for the base calibration (design + refinement)
    int refine_runs = 3;           // evaluations per augmented candidate fit
    int max_candidates = 2;        // top-ranked effects fitted as augmented models
    int max_effects = 2;           // stepwise: effects added one at a time while BIC improves
    // Runs per refinement batch of the calibration: part of the method (which points are
    // run depends on it), so the report depends on it and on nothing of the machine.
    int batch_runs = 2;
    int concurrency = 2;           // model evaluations run at the same time (the report does not depend on it)
    int threads_per_run = 1;       // OpenMP threads inside one DEM run
    // DEM: cap on soil particles per run (0 = the scheme's): the calibration specimen.
    int max_particles = 200;
    int packings_per_run = 1;      // DEM: packings averaged into one model run (1..16)
    // DEM: the lab specimen's relative density D_r (0 = loosest, 1 = densest) when the lab
    // states it: the model's packing density is held at it (compaction_friction_for) instead
    // of calibrated.
    std::optional<double> relative_density;
    std::uint64_t seed = 1;
    // Packings the calibrated base model is run on to measure the noise floor (the
    // calibration's own counts as one; 1 = not measured, every gain is taken at face value).
    int noise_seeds = 3;
    double bic_threshold = 10.0;   // an effect is kept only if it lowers BIC by more than this
    // Uncertainties from a forward-difference Jacobian at the optimum (k extra runs per
    // reported model); false: from the local regression over the runs already made
    // (cheaper, and on a rough DEM response less sensitive to the step).
    bool finite_difference_uncertainty = true;
};

struct FittedParameter {
    std::string name;
    std::string unit;  // SI
    double value = 0.0;
    double std = 0.0;  // 1-sigma from the local Jacobian, inflated for correlated readings
};

// Error of one curve (or one phase of it). unit is the SI unit of the compared quantity.
struct PhaseError {
    std::string curve;   // "stress_strain@100kPa", "volumetric@100kPa", "creep-2@100kPa"
    std::string phase;   // "all", "pre_peak", "post_peak", "contraction", "dilation",
                         // "instant", "primary", "steady", "tertiary"
    std::string unit;    // "Pa" or "-"
    std::size_t n = 0;            // readings the model reached
    std::size_t n_unreached = 0;  // readings beyond the model curve's range (not in rmse)
    double rmse = 0.0;
    double nrmse = 0.0;  // rmse / range of the lab curve (whole curve, so phases add up)
};

struct CandidateResult {
    int step = 1;                  // stepwise selection step (1 = against the base model)
    std::string effect;
    double signature_score = 0.0;  // |correlation| of residual with the effect's signature, 0..1
    bool fitted = false;
    std::vector<FittedParameter> parameters;  // effect parameters only
    double rss = 0.0;                         // normalised residual sum of squares after fit
    double bic = 0.0;
    double delta_bic_vs_base = 0.0;           // vs the model of this step without it; negative = better
    double nrmse = 0.0;                       // pooled NRMSE after fit
    // Paired gains: the pooled NRMSE of the step's model without the effect less the one
    // with it, both run on the same packing, one per packing (the calibration's first,
    // then the noise floor's). Empty when the candidate did not reach that test.
    std::vector<double> paired_gains;
    std::string note;                         // why it was not fitted / failed
};

struct RunnerUp {
    std::string effect;
    double delta_bic = 0.0;  // BIC(runner-up) - BIC(chosen); positive = worse
};

// One step of the stepwise selection: the model before it, the effect kept (or none).
struct SelectionStep {
    int step = 1;
    std::string added;           // effect kept at this step, "" if none earned its parameters
    double nrmse_before = 0.0;   // pooled NRMSE of the model entering the step (refined)
    double nrmse_after = 0.0;    // with the effect added
    double delta_bic = 0.0;      // BIC(with) - BIC(without), n_eff of the step
    double n_effective = 0.0;
    // A test artefact's gain in pooled NRMSE on each packing (the calibration's first, then
    // the noise floor's), the final model with and without it each at its own point; empty
    // for a physical effect's step (its candidate carries them) or with one packing.
    std::vector<double> paired_gains;
    // A test artefact's gain on each confining pressure of the calibration's packing
    // (pressure Pa, NRMSE gain); empty for a physical effect's step.
    std::vector<std::pair<double, double>> gain_by_confining;
};

// Why a catalog effect was not tested.
struct NotTestable {
    std::string effect;
    std::string reason;
};

// A base parameter that ended at the edge of its prior.
struct BoundHit {
    std::string name;
    std::string unit;
    double value = 0.0;
    bool upper = false;
};

// The outcome a user acts on:
//   effect_found      effects were named and the final model fits within the tolerance;
//   no_effect_needed  the calibrated base model fits within the tolerance, no effect earns
//                     its parameters beyond the noise floor;
//   unexplained       what remains is above kUnexplainedFactor x tolerance (pooled, or in one
//                     curve phase), or one curve is above kUnexplainedFactor x its own
//                     tolerance (its own packing scatter) and kUnexplainedFloor,
//                     whatever the catalog adds; effects that helped are still listed in
//                     `effects`.
enum class Outcome { EffectFound, NoEffectNeeded, Unexplained };
// Inline: the report's JSON edge (and its fuzz target) names outcomes without the engine.
inline std::string_view outcome_name(Outcome o) {
    switch (o) {
        case Outcome::EffectFound: return "effect_found";
        case Outcome::NoEffectNeeded: return "no_effect_needed";
        case Outcome::Unexplained: return "unexplained";
    }
    return "unexplained";
}

// A residual is unexplained above this multiple of the noise floor's tolerance, and never
// below kUnexplainedFloor of a lab curve's range pooled (twice both in one curve phase): a
// model of another family (another DEM contact law, an analytic stand-in) fitted to a plain
// material leaves a few % of systematic misfit that no effect should be blamed for
// (docs/diagnosis.md).
inline constexpr double kUnexplainedFactor = 2.0;
inline constexpr double kUnexplainedFloor = 0.05;

struct DiagnosisReport {
    Outcome outcome = Outcome::Unexplained;
    // Headline: the first physical effect kept, else the first artefact named, else "none"
    // (no_effect_needed) or "unexplained".
    std::string chosen_effect = "unexplained";
    std::vector<std::string> effects;           // every effect kept (stepwise order)
    std::vector<FittedParameter> parameters;    // final model: base then effect parameters
    std::vector<FittedParameter> base_parameters;  // calibrated base model alone
    std::vector<PhaseError> error_before;       // calibrated base model
    std::vector<PhaseError> error_after;        // final model
    double delta_bic_vs_base = 0.0;
    std::vector<RunnerUp> runners_up;
    std::vector<CandidateResult> candidates;    // every effect considered, per step, ranked
    std::vector<SelectionStep> steps;
    double n_readings = 0.0;
    double n_effective = 0.0;
    double nrmse_before = 0.0;                  // pooled over the readings the model reached
    double nrmse_after = 0.0;
    std::size_t unreached_before = 0;           // readings the model did not reach (not in NRMSE)
    std::size_t unreached_after = 0;
    NoiseFloor noise;                           // packing scatter, lab noise, tolerance
    // Weight of each kind of test in the fit (fit_weights.hpp); empty: every reading 1.
    std::vector<std::pair<std::string, double>> fit_weights;
    PhaseError worst_remaining;                 // the final model's largest phase error
    std::vector<HeldParameter> held_fixed;      // settings the fit took as given
    std::vector<NotTestable> not_testable;      // catalog effects not tried, with the reason
    std::vector<BoundHit> at_bounds;            // base parameters at the edge of their prior
    std::vector<std::string> artefacts_below_threshold;  // kept as corrections, not named
    std::vector<std::string> artefacts_dropped;          // did not lower BIC
    LabDataset base_curves;                     // calibrated base model at the lab's conditions
    LabDataset final_curves;                    // final model (artefacts applied)
    int runs_used = 0;
    int failed_runs = 0;                        // points whose run and its retry both failed
    int retried_runs = 0;                       // runs that failed once and were run again
    std::vector<std::string> failure_messages;  // the engine's messages (first few, distinct)
};

// Observer: progress, candidate events and cancellation. on_progress and on_candidate are
// called from the calling thread; cancelled() also from worker threads (inside DEM runs),
// so it must be thread-safe (e.g. read an atomic flag).
class DiagnoseObserver {
public:
    virtual ~DiagnoseObserver() = default;
    virtual void on_progress(double percent, std::string_view stage) {}
    virtual void on_candidate(const CandidateResult& candidate) {}
    virtual bool cancelled() const { return false; }
};

// Thrown when the observer cancels; the service marks the job cancelled.
struct DiagnosisCancelled : std::exception {
    const char* what() const noexcept override { return "diagnosis cancelled"; }
};

class SimulationBatch;

// Core loop on any forward model. Throws std::invalid_argument on unusable lab data.
// The forward runs go through `batch` (threads, or MPI ranks); without it, through
// options.concurrency threads.
DiagnosisReport run_diagnosis(const LabDataset& lab, const ForwardModel& model,
                              const DiagnoseOptions& options, DiagnoseObserver& observer);
DiagnosisReport run_diagnosis(const LabDataset& lab, const ForwardModel& model, const DiagnoseOptions& options,
                              DiagnoseObserver& observer, SimulationBatch& batch);

// What a diagnosis will cost before it starts: model runs at most (design, refinement,
// candidates, noise floor, uncertainty), at least, and engine runs per model run (one per
// confining pressure).
struct DiagnosisPlan {
    int model_runs = 0;
    // What every diagnosis runs whatever the residual shows: its calibration budget, the
    // noise floor's other packings and the base model's finite-difference uncertainty (k
    // runs, k = base parameters): budget_runs + (noise_seeds - 1) + (fd uncertainty ? k : 0).
    // The effect search (signatures, candidate fits) comes on top of it.
    int model_runs_low = 0;
    // A diagnosis that searches one effect step: model_runs_low, the kinds' weighing on data
    // with shear curves and creep stages (w), and the search's share of one of max_effects
    // steps, ceil((model_runs - model_runs_low - w) / max_effects). The
    // bound counts every step with every candidate passing BIC; most diagnoses stop after
    // one step (measured on the outside suite: docs/diagnosis.md section 5).
    int model_runs_expected = 0;
    int engine_runs_per_model_run = 1;
};
DiagnosisPlan plan_diagnosis(const LabDataset& lab, const ForwardModel& model, const DiagnoseOptions& options);

// Step 2 alone, without calibration: the catalog ranked by signature score at the given
// base parameter values (SI, ordered as model.base_parameters()). Costs 1 + k + (number of
// physical effects) model runs. For a quick "what is missing here" and for tests on
// engine data where a whole loop is too slow.
std::vector<CandidateResult> rank_effects(const LabDataset& lab, const ForwardModel& model,
                                          const std::vector<double>& base_values, const DiagnoseOptions& options,
                                          DiagnoseObserver& observer);

// The product entry point: the forward model is the DEM triaxial protocol built on `base`.
DiagnosisReport run_diagnosis(const LabDataset& lab, const protocol::TestScheme& base,
                              const DiagnoseOptions& options, DiagnoseObserver& observer);
DiagnosisReport run_diagnosis(const LabDataset& lab, const protocol::TestScheme& base, const DiagnoseOptions& options,
                              DiagnoseObserver& observer, SimulationBatch& batch);

}  // namespace triax::diagnose
