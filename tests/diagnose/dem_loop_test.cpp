// The whole loop on lab data made by the ENGINE (issue 6): a reduced DEM specimen with an
// effect switched on that the diagnosis is not told about, read like a lab (0.1 % strain
// steps, Gaussian noise, a smooth seating closure of 0.3 %), from ANOTHER packing than the
// one the diagnosis runs (lab seed 7, model seed 11): the model cannot reproduce the
// specimen's own stick-slip history, as with a real specimen. Hidden effects: rolling
// resistance (100 kPa) and grain crushing (50 and 200 kPa). A control dataset (same noise
// and seating, no effect) must not be given a physical effect, with every physical
// candidate (rolling resistance, grain breakage) in competition.
// CI runs the rolling-resistance case and the control; the crushing case is run by hand
// (tag [.dem-crush]). Figures and why in docs/diagnosis.md section 8.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "engine/diagnose/dem_forward_model.hpp"
#include "engine/diagnose/diagnosis.hpp"
#include "server/io/diagnosis_verdict.hpp"
#include "engine/diagnose/model_selection.hpp"
#include "engine/diagnose/residuals.hpp"
#include "engine/diagnose/test_artefacts.hpp"
#include "engine/protocol/test_scheme.hpp"
#include "lab_fixtures.hpp"
#include "synthetic_lab.hpp"

using namespace triax::diagnose;
using namespace triax::diagnose::testing;
using triax::protocol::TestScheme;

namespace {

// The engine-made labs' relative density: medium-dense (compaction friction 0.25 x mu).
constexpr double kCaseRelativeDensity = 0.75;

struct Case {
    DiagnosisReport report;
    double seconds = 0.0;
    int planned_runs = 0;  // plan_diagnosis: the figure the progress bar and the cost estimate show
};

// One engine-made dataset and its diagnosis. Defaults: the rolling-resistance CI case.
struct CaseSpec {
    std::vector<std::pair<Effect, std::vector<double>>> hidden;
    std::vector<double> truth_scale;  // multiplies the nominal base values (empty: the truth is the start)
    // Reduced specimen 50 x 100 mm, grains of 2.0-6.0 mm radius (about 400; at 2.5 mm, ~200
    // grains, a 2 % change of the contact modulus moved q by 16 %: too rough to calibrate
    // rolling resistance), sheared to 3 % (the hidden rolling resistance doubles q by 1 %,
    // and the base model's curve flattens after 2 % while it keeps hardening;
    // docs/diagnosis.md section 8.2).
    double r_min_m = 2.0e-3;
    std::vector<double> confining_pa{100e3};
    std::uint64_t lab_seed = 7;    // the packing the "lab" specimen is made from
    std::uint64_t model_seed = 11; // the diagnosis's
    int budget_runs = 7;
    int refine_runs = 4;
};

Case run_case(const CaseSpec& cs) {
    const TestScheme base = reduced_scheme(cs.r_min_m, 0.03, cs.model_seed);
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

std::string describe(const Case& c) {
    const auto& r = c.report;
    std::string t = triax::io::diagnosis_verdict(r) + "\nwall " + std::to_string(c.seconds) + " s, n_eff " + std::to_string(r.n_effective) +
                    " of " + std::to_string(r.n_readings) + "\n";
    for (const auto& s : r.steps)
        t += "step " + std::to_string(s.step) + " +" + s.added + " nrmse " + std::to_string(s.nrmse_before) + " -> " +
             std::to_string(s.nrmse_after) + " dBIC " + std::to_string(s.delta_bic) + " n_eff " +
             std::to_string(s.n_effective) + "\n";
    for (const auto& cd : r.candidates)
        t += "  step " + std::to_string(cd.step) + " " + cd.effect + " score " + std::to_string(cd.signature_score) +
             " dBIC " + std::to_string(cd.delta_bic_vs_base) + " " + cd.note + "\n";
    for (const auto& b : r.error_before) {
        if (b.phase != "all") continue;
        auto a = std::find_if(r.error_after.begin(), r.error_after.end(), [&](auto& e) { return e.curve == b.curve && e.phase == "all"; });
        t += "  " + b.curve + " nrmse " + std::to_string(b.nrmse) + " -> " + (a != r.error_after.end() ? std::to_string(a->nrmse) : "?") + "\n";
    }
    for (const auto& p : r.parameters) t += "  " + p.name + " = " + std::to_string(p.value) + " +- " + std::to_string(p.std) + "\n";
    t += "  base model alone:";
    for (const auto& p : r.base_parameters) t += " " + p.name + " = " + std::to_string(p.value);
    t += "\n";
    return t;
}

// The hidden effect is named, and the step that adds it and the whole loop at least halve
// the error with delta BIC < -10; its (first) parameter is at least `min_value`.
void check_named(const Case& c, const std::string& effect, const std::string& parameter, double min_value) {
    const auto& r = c.report;
    CHECK(r.chosen_effect == effect);
    CHECK(r.nrmse_after <= 0.5 * r.nrmse_before);
    auto step = std::find_if(r.steps.begin(), r.steps.end(), [&](auto& s) { return s.added == effect; });
    REQUIRE(step != r.steps.end());
    CHECK(step->nrmse_after <= 0.5 * step->nrmse_before);
    CHECK(step->delta_bic < -10.0);
    auto p = std::find_if(r.parameters.begin(), r.parameters.end(), [&](auto& q) { return q.name == parameter; });
    REQUIRE(p != r.parameters.end());
    CHECK(p->value >= min_value);
}

void check_no_physical_effect(const Case& c) {
    for (const auto& e : c.report.effects) CHECK(is_test_artefact(*effect_from_name(e)));
    CHECK(c.report.outcome != Outcome::Unexplained);
    CHECK((c.report.chosen_effect == "none" || c.report.chosen_effect == "seating_error"));
}

double rmse_of(const DiagnosisReport& r, const std::string& curve) {
    for (const auto& e : r.error_before)
        if (e.curve == curve && e.phase == "all") return e.rmse;
    FAIL("no error for " << curve);
    return 0.0;
}

// Hidden grain crushing: crushability 0.75 (sigma0 0.8 MPa; the candidate's nominal 1 is
// the presets' 0.6 MPa) at 50 and 200 kPa, lab packing 13, model packing 17 (on the pair
// 7/11 the loop fails today: see the hidden case below and docs/diagnosis.md 8.8). Reduced specimen of ~200 grains (r_min 2.5 mm)
// to keep two pressures per run in budget: crushing's signal is large against its packing
// scatter (at 200 kPa, 2 % strain: +1.3 % volumetric strain and -20 % q for x = 0.75, against
// +-0.2 % and +-12 % between packings; docs/diagnosis.md section 8.7).
// At 50 and 200 kPa: at 100 kPa alone the calibrated base took the effect up as friction
// and bond strength (one pressure cannot tell cohesion from interlocking; docs/diagnosis.md 8.3).
CaseSpec rolling_case() {
    CaseSpec cs;
    cs.hidden = {{Effect::RollingResistance, {0.25}}};
    cs.confining_pa = {50e3, 200e3};
    return cs;
}

CaseSpec crushing_case(std::vector<std::pair<Effect, std::vector<double>>> hidden) {
    CaseSpec cs;
    cs.hidden = std::move(hidden);
    cs.r_min_m = 2.5e-3;
    cs.confining_pa = {50e3, 200e3};
    cs.budget_runs = 6;
    cs.refine_runs = 3;
    cs.lab_seed = 13;
    cs.model_seed = 17;
    return cs;
}

void check_crushing_named(const Case& c) {
    check_named(c, "bond_degradation", "grain_crushability", 0.1 * kCrushabilityMax);
    // Its signature: the base model's misfit of the volumetric strain grows with sigma3.
    CHECK(rmse_of(c.report, "volumetric@200kPa") > 2.0 * rmse_of(c.report, "volumetric@50kPa"));
}

}  // namespace

TEST_CASE("DEM data: hidden rolling resistance is named and the error at least halved", "[diagnose][dem][slow]") {
    const auto c = run_case(rolling_case());
    UNSCOPED_INFO(describe(c));
    check_named(c, "rolling_resistance", "rolling_friction", 0.1);  // the size, not the value (mu trades with mu_r)
    CHECK(c.report.runs_used <= c.planned_runs);  // the plan the user was shown holds
    WARN(describe(c));
}

TEST_CASE("DEM data: control (noise + seating, no effect) is not given a physical effect", "[diagnose][dem][slow]") {
    const auto c = run_case({});
    UNSCOPED_INFO(describe(c));
    check_no_physical_effect(c);
    CHECK(c.report.runs_used <= c.planned_runs);  // the plan the user was shown holds
    // Always shown, so the measured figures can be read off the CI log.
    WARN(describe(c));
}

// Run by hand (10-13 min of one core; it kept CI above its budget):
//   ./build/tests/test_diagnose "[.dem-crush]" -s
TEST_CASE("DEM data: hidden grain crushing at 50 and 200 kPa is named as grain breakage", "[diagnose][dem][.dem-crush]") {
    const auto c = run_case(crushing_case({{Effect::BondDegradation, {0.75}}}));
    UNSCOPED_INFO(describe(c));
    check_crushing_named(c);
    CHECK(c.report.runs_used <= c.planned_runs);  // the plan the user was shown holds
    WARN(describe(c));
}

// Robustness checks run by hand (not in CI, ~2-3 min each):
//   ./build/tests/test_diagnose "[.dem-loop]" -s
// the truth away from the calibration's start (modulus x1.4, friction 0.5, bonds x0.5)
// and another lab packing.
TEST_CASE("DEM data, off-nominal truth: hidden rolling resistance", "[diagnose][dem][.dem-loop]") {
    const auto c = run_case({{{Effect::RollingResistance, {0.25}}}, {1.4, 1.25, 0.5}, 2.0e-3, {100e3}, 13, 11, 8, 4});
    WARN(describe(c));
    CHECK(c.report.chosen_effect == "rolling_resistance");
    CHECK(c.report.nrmse_after <= 0.5 * c.report.nrmse_before);
}

TEST_CASE("DEM data, off-nominal truth: control", "[diagnose][dem][.dem-loop]") {
    const auto c = run_case({{}, {1.4, 1.25, 0.5}, 2.0e-3, {100e3}, 13, 11, 8, 4});
    WARN(describe(c));
    for (const auto& e : c.report.effects) CHECK(is_test_artefact(*effect_from_name(e)));
}

// The CI cases with another lab/model packing pair (lab seed 13, model seed 17), CI options:
//   ./build/tests/test_diagnose "[.dem-seeds]" -s
TEST_CASE("DEM data (other packing pair): hidden rolling resistance", "[diagnose][dem][.dem-seeds]") {
    CaseSpec cs = rolling_case();
    cs.lab_seed = 13, cs.model_seed = 17;
    const auto c = run_case(cs);
    WARN(describe(c));
    check_named(c, "rolling_resistance", "rolling_friction", 0.1);
}

TEST_CASE("DEM data (other packing pair): control", "[diagnose][dem][.dem-seeds]") {
    CaseSpec cs;
    cs.lab_seed = 13, cs.model_seed = 17;
    const auto c = run_case(cs);
    WARN(describe(c));
    check_no_physical_effect(c);
}

// Known failure (not in CI; run `test_diagnose "[.dem-crush-gap]"`): on the packing pair
// lab 7 / model 11 the base calibration drifts to friction 0.12 and modulus 800 MPa (a Latin
// hypercube point that really is the better base model for crushed data: 31.5 % against
// 42.9 % at the prior), and the best crushing fit (20.7 %, delta BIC -5.5) is from there:
// the prior with crushing 1 fits this lab packing worse (29.0 %; the truth 0.75: 14.2 %).
// Neither multi-start candidate fits
// nor a line search along the effect changed it (docs/diagnosis.md 8.9): the misfit at the
// prior base varies 10-22 % for crushability 0.6-0.9 on ~200 grains, so the 50 % cut is at
// this pair's noise floor (8.10). Un-hide it when the loop passes it.
TEST_CASE("DEM data (packing pair 7/11): hidden grain crushing", "[diagnose][dem][.dem-crush-gap]") {
    CaseSpec cs = crushing_case({{Effect::BondDegradation, {0.75}}});
    cs.lab_seed = 7, cs.model_seed = 11;
    const auto c = run_case(cs);
    WARN(describe(c));
    check_crushing_named(c);
}

// The floor of the crushing case on a packing pair: the NRMSE of the TRUE model (nominal
// base, crushability 0.75) run on the model's packing against the lab made on the other
// packing, seating profiled on a grid (membrane 0, as in the lab). If this floor is above
// half the base model's misfit, no calibration can cut the error by 50 % on that pair.
//   ./build/tests/test_diagnose "[.dem-crush-floor]" -s
TEST_CASE("DEM data: floor of the crushing case at the true parameters, both packing pairs", "[diagnose][dem][.dem-crush-floor]") {
    for (auto [lab_seed, model_seed] : {std::pair<std::uint64_t, std::uint64_t>{7, 11}, {13, 17}}) {
        CaseSpec cs = crushing_case({{Effect::BondDegradation, {0.75}}});
        const TestScheme base = reduced_scheme(cs.r_min_m, 0.03, model_seed);
        const DemForwardModel model(base, shear_conditions(cs.confining_pa, 0.03), 1, 0, nullptr, 1, kCaseRelativeDensity);
        std::vector<double> truth;
        for (const auto& s : model.base_parameters()) truth.push_back(s.nominal);
        SyntheticLabOptions lo;
        lo.seating_strain = 0.003;
        lo.deviator_noise_pa = 3000.0;
        lo.volumetric_noise = 2e-4;
        lo.shear_strain_step = 0.001;
        lo.shear_readings = 30;
        lo.seed = lab_seed;
        const LabDataset lab = make_synthetic_lab(model, {truth, cs.hidden}, lo);
        const auto layout = residual_layout(lab);
        const LabDataset at_truth = model.simulate({truth, cs.hidden}, model_seed);
        double best = 1e9, best_s = 0.0;
        for (int g = 0; g <= 20; ++g) {
            LabDataset d = at_truth;
            apply_test_artefact(d, Effect::SeatingError, {0.0005 * g});
            const auto r = normalised_residual(layout, d);
            const double nrmse = std::sqrt(residual_sum_of_squares(r) / static_cast<double>(r.size()));
            if (nrmse < best) best = nrmse, best_s = 0.0005 * g;
        }
        WARN("packing pair " << lab_seed << "/" << model_seed << ": true model NRMSE " << 100.0 * best
                             << " % (seating " << 100.0 * best_s << " %)");
        CHECK(best < 1.0);
    }
}
