#pragma once
// The DEM loop cases (tests/diagnose/dem_loop_test.cpp; bench/dem_loop_packings.cpp runs
// them over packing pairs): a reduced DEM specimen with an effect switched on that the
// diagnosis is not told about, read like a lab (0.1 % strain steps, Gaussian noise, a
// smooth seating closure of 0.3 %), from ANOTHER packing than the one the diagnosis runs:
// the model cannot reproduce the specimen's own stick-slip history, as with a real
// specimen. Each rule a case must meet is returned as the description of the rules it
// failed, so the test asserts them and the bench counts them per packing pair.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "engine/diagnose/dem_forward_model.hpp"
#include "engine/diagnose/diagnosis.hpp"
#include "engine/diagnose/model_selection.hpp"
#include "engine/diagnose/residuals.hpp"
#include "engine/diagnose/test_artefacts.hpp"
#include "engine/protocol/test_scheme.hpp"
#include "server/io/diagnosis_verdict.hpp"
#include "tests/diagnose/lab_fixtures.hpp"
#include "tests/diagnose/synthetic_lab.hpp"

namespace triax::diagnose::testing {

// The engine-made labs' relative density: medium-dense (compaction friction 0.25 x mu).
constexpr double kCaseRelativeDensity = 0.75;

struct Case {
    DiagnosisReport report;
    double seconds = 0.0;
    int planned_runs = 0;  // plan_diagnosis: the figure the progress bar and the cost estimate show
};

// One engine-made dataset and its diagnosis. Defaults: the rolling-resistance case's
// specimen. Reduced specimen 50 x 100 mm, grains of 2.0-6.0 mm radius (about 400; at 2.5
// mm, ~200 grains, a 2 % change of the contact modulus moved q by 16 %: too rough to
// calibrate rolling resistance), sheared to 3 % (the hidden rolling resistance doubles q by
// 1 %, and the base model's curve flattens after 2 % while it keeps hardening;
// docs/diagnosis.md section 8.2).
struct CaseSpec {
    std::vector<std::pair<Effect, std::vector<double>>> hidden;
    std::vector<double> truth_scale;  // multiplies the nominal base values (empty: the truth is the start)
    double r_min_m = 2.0e-3;
    std::vector<double> confining_pa{100e3};
    std::uint64_t lab_seed = 7;    // the packing the "lab" specimen is made from
    std::uint64_t model_seed = 11; // the diagnosis's
    int budget_runs = 7;
    int refine_runs = 4;
};

inline Case run_case(const CaseSpec& cs) {
    const protocol::TestScheme base = triax::testing::reduced_scheme(cs.r_min_m, 0.03, cs.model_seed);
    // The lab states its specimen's density: these cases test an effect against the base at
    // a known density, as a lab that reports D_r has it (a calibrated density trades with
    // rolling resistance on 3 % of strain).
    const DemForwardModel model(base, shear_conditions(cs.confining_pa, 0.03), 1, 0, nullptr, 1, kCaseRelativeDensity);
    std::vector<double> truth;
    for (const auto& s : model.base_parameters()) truth.push_back(s.nominal);
    for (std::size_t j = 0; j < truth.size() && j < cs.truth_scale.size(); ++j) truth[j] *= cs.truth_scale[j];
    SyntheticLabOptions lo;
    lo.seating_strain = 0.003;
    lo.deviator_noise_pa = 3000.0;
    lo.volumetric_noise = 2e-4;
    lo.shear_strain_step = 0.001;
    lo.shear_readings = 30;  // 0 .. 2.9 %, inside the model's 3 %
    lo.seed = cs.lab_seed;   // another packing than the diagnosis's (model_seed)
    const LabDataset lab = make_synthetic_lab(model, {truth, cs.hidden}, lo);

    DiagnoseOptions opt;
    opt.budget_runs = cs.budget_runs;
    opt.refine_runs = cs.refine_runs;
    opt.max_candidates = 1;
    opt.max_effects = 1;
    opt.concurrency = 2;
    opt.seed = cs.model_seed;
    opt.finite_difference_uncertainty = false;
    DiagnoseObserver quiet;
    const auto t0 = std::chrono::steady_clock::now();
    Case out{run_diagnosis(lab, model, opt, quiet), 0.0, plan_diagnosis(lab, model, opt).model_runs};
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

inline std::string describe(const Case& c) {
    const auto& r = c.report;
    std::string t = triax::io::diagnosis_verdict(r) + "\nwall " + std::to_string(c.seconds) + " s, n_eff " +
                    std::to_string(r.n_effective) + " of " + std::to_string(r.n_readings) + "\n";
    for (const auto& s : r.steps)
        t += "step " + std::to_string(s.step) + " +" + s.added + " nrmse " + std::to_string(s.nrmse_before) + " -> " +
             std::to_string(s.nrmse_after) + " dBIC " + std::to_string(s.delta_bic) + " n_eff " +
             std::to_string(s.n_effective) + "\n";
    for (const auto& cd : r.candidates)
        t += "  step " + std::to_string(cd.step) + " " + cd.effect + " score " + std::to_string(cd.signature_score) +
             " dBIC " + std::to_string(cd.delta_bic_vs_base) + " " + cd.note + "\n";
    for (const auto& b : r.error_before) {
        if (b.phase != "all") continue;
        auto a = std::find_if(r.error_after.begin(), r.error_after.end(),
                              [&](auto& e) { return e.curve == b.curve && e.phase == "all"; });
        t += "  " + b.curve + " nrmse " + std::to_string(b.nrmse) + " -> " +
             (a != r.error_after.end() ? std::to_string(a->nrmse) : "?") + "\n";
    }
    for (const auto& p : r.parameters) t += "  " + p.name + " = " + std::to_string(p.value) + " +- " + std::to_string(p.std) + "\n";
    t += "  base model alone:";
    for (const auto& p : r.base_parameters) t += " " + p.name + " = " + std::to_string(p.value);
    t += "\n";
    return t;
}

// The hidden effect is named, and the step that adds it and the whole loop at least halve
// the error with delta BIC < -10; its (first) parameter is at least `min_value`; the run
// count stays within the plan the user was shown.
inline std::vector<std::string> named_failures(const Case& c, const std::string& effect, const std::string& parameter,
                                               double min_value) {
    std::vector<std::string> failed;
    const auto& r = c.report;
    if (r.chosen_effect != effect) failed.push_back("chose " + r.chosen_effect + ", not " + effect);
    if (r.nrmse_after > 0.5 * r.nrmse_before) failed.push_back("loop did not halve the error");
    auto step = std::find_if(r.steps.begin(), r.steps.end(), [&](auto& s) { return s.added == effect; });
    if (step == r.steps.end()) {
        failed.push_back("no step adds " + effect);
    } else {
        if (step->nrmse_after > 0.5 * step->nrmse_before) failed.push_back("its step did not halve the error");
        if (step->delta_bic >= -10.0) failed.push_back("its step's delta BIC >= -10");
    }
    auto p = std::find_if(r.parameters.begin(), r.parameters.end(), [&](auto& q) { return q.name == parameter; });
    if (p == r.parameters.end())
        failed.push_back("no parameter " + parameter);
    else if (p->value < min_value)
        failed.push_back(parameter + " below " + std::to_string(min_value));
    if (r.runs_used > c.planned_runs) failed.push_back("more runs than planned");
    return failed;
}

// No physical effect is named or kept, and the verdict is not "unexplained".
inline std::vector<std::string> control_failures(const Case& c) {
    std::vector<std::string> failed;
    for (const auto& e : c.report.effects)
        if (!is_test_artefact(*effect_from_name(e))) failed.push_back("physical effect " + e + " kept");
    if (c.report.outcome == Outcome::Unexplained) failed.push_back("unexplained");
    if (c.report.chosen_effect != "none" && c.report.chosen_effect != "seating_error")
        failed.push_back("chose " + c.report.chosen_effect);
    if (c.report.runs_used > c.planned_runs) failed.push_back("more runs than planned");
    return failed;
}

inline double rmse_of(const DiagnosisReport& r, const std::string& curve) {
    for (const auto& e : r.error_before)
        if (e.curve == curve && e.phase == "all") return e.rmse;
    return NAN;
}

// Hidden grain crushing: crushability 0.75 (sigma0 0.8 MPa; the candidate's nominal 1 is
// the presets' 0.6 MPa) at 50 and 200 kPa. Reduced specimen of ~200 grains (r_min 2.5 mm)
// to keep two pressures per run in budget: crushing's signal is large against its packing
// scatter (at 200 kPa, 2 % strain: +1.3 % volumetric strain and -20 % q for x = 0.75,
// against +-0.2 % and +-12 % between packings; docs/diagnosis.md section 8.7). At 50 and
// 200 kPa: at 100 kPa alone the calibrated base took the effect up as friction and bond
// strength (one pressure cannot tell cohesion from interlocking; docs/diagnosis.md 8.3).
inline CaseSpec rolling_case() {
    CaseSpec cs;
    cs.hidden = {{Effect::RollingResistance, {0.25}}};
    cs.confining_pa = {50e3, 200e3};
    return cs;
}

inline CaseSpec control_case() { return CaseSpec{}; }

inline CaseSpec crushing_case() {
    CaseSpec cs;
    cs.hidden = {{Effect::BondDegradation, {0.75}}};
    cs.r_min_m = 2.5e-3;
    cs.confining_pa = {50e3, 200e3};
    cs.budget_runs = 6;
    cs.refine_runs = 3;
    cs.lab_seed = 13;
    cs.model_seed = 17;
    return cs;
}

inline std::vector<std::string> rolling_failures(const Case& c) {
    return named_failures(c, "rolling_resistance", "rolling_friction", 0.1);  // the size, not the value (mu trades with mu_r)
}

// Named as grain breakage, with its signature: the base model's misfit of the volumetric
// strain grows with sigma3.
inline std::vector<std::string> crushing_failures(const Case& c) {
    auto failed = named_failures(c, "bond_degradation", "grain_crushability", 0.1 * kCrushabilityMax);
    if (!(rmse_of(c.report, "volumetric@200kPa") > 2.0 * rmse_of(c.report, "volumetric@50kPa")))
        failed.push_back("volumetric misfit at 200 kPa not above twice the one at 50 kPa");
    return failed;
}

}  // namespace triax::diagnose::testing
