// The whole loop on lab data made by the ENGINE (issue 6): a reduced DEM specimen with
// rolling resistance switched on that the diagnosis is not told about, read like a lab
// (0.1 % strain steps, Gaussian noise, a smooth seating closure of 0.3 %), from ANOTHER
// packing than the one the diagnosis runs (lab seed 7, model seed 11): the model cannot
// reproduce the specimen's own stick-slip history, as with a real specimen. A control
// dataset (same noise and seating, no effect) must not be given a physical effect.
// CI budget: 17-19 reduced runs per case (one pressure, shear to 3 %, 2 workers, budget
// 7/4 plus one run on another packing for the model's packing scatter); figures and why
// in docs/diagnosis.md section 8.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <string>

#include "engine/diagnose/dem_forward_model.hpp"
#include "engine/diagnose/diagnosis.hpp"
#include "engine/protocol/test_scheme.hpp"
#include "synthetic_lab.hpp"

using namespace triax::diagnose;
using triax::protocol::TestScheme;

namespace {

// Reduced specimen 50 x 100 mm, grains of 2.0-6.0 mm radius (about 400; at 2.5 mm, ~200
// grains, a 2 % change of the contact modulus moved q by 16 %: too rough to calibrate),
// sheared to 3 % (the hidden rolling resistance doubles q by 1 %, and the base model's
// curve flattens after 2 % while it keeps hardening; docs/diagnosis.md section 8.2).
TestScheme ci_scheme(std::uint64_t model_seed = 11) {
    TestScheme s;
    s.name = "reduced";
    s.specimen.diameter_m = 0.05;
    s.specimen.height_m = 0.1;
    s.gradation.r_min_m = 2.0e-3;
    s.gradation.radius_ratio = 3.0;
    s.loading.max_axial_strain = 0.03;
    s.seed = model_seed;
    return s;
}

struct Case {
    DiagnosisReport report;
    double seconds = 0.0;
};

// truth_scale multiplies the nominal base values (1: the truth is the calibration's start);
// lab_seed is the packing the "lab" specimen is made from, model_seed the diagnosis's.
Case run_case(const std::vector<std::pair<Effect, std::vector<double>>>& hidden, std::vector<double> truth_scale = {},
              std::uint64_t lab_seed = 7, int budget_runs = 7, int refine_runs = 4, std::uint64_t model_seed = 11) {
    const TestScheme base = ci_scheme(model_seed);
    LabDataset conditions;
    LabCurve c;
    c.kind = CurveKind::Shear;
    c.confining_pa = 100e3;
    c.axial_strain = {0.0, 0.03};
    c.deviator_pa = {0.0, 1e5};
    conditions.curves.push_back(c);
    const DemForwardModel model(base, conditions, 1, 0);
    std::vector<double> truth;
    for (const auto& s : model.base_parameters()) truth.push_back(s.nominal);
    for (std::size_t j = 0; j < truth.size() && j < truth_scale.size(); ++j) truth[j] *= truth_scale[j];
    testing::SyntheticLabOptions lo;
    lo.seating_strain = 0.003;
    lo.deviator_noise_pa = 3000.0;
    lo.volumetric_noise = 2e-4;
    lo.shear_strain_step = 0.001;
    lo.shear_readings = 30;  // 0 .. 2.9 %, inside the model's 3 %
    lo.seed = lab_seed;      // another packing than the diagnosis's (model_seed)
    const LabDataset lab = testing::make_synthetic_lab(model, {truth, hidden}, lo);

    DiagnoseOptions opt;
    opt.budget_runs = budget_runs;
    opt.refine_runs = refine_runs;
    opt.max_candidates = 1;
    opt.max_effects = 1;
    opt.concurrency = 2;
    opt.seed = model_seed;
    opt.finite_difference_uncertainty = false;
    DiagnoseObserver quiet;
    const auto t0 = std::chrono::steady_clock::now();
    Case out{run_diagnosis(lab, model, opt, quiet), 0.0};
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

std::string describe(const Case& c) {
    const auto& r = c.report;
    std::string t = r.verdict + "\nwall " + std::to_string(c.seconds) + " s, n_eff " + std::to_string(r.n_effective) +
                    " of " + std::to_string(r.n_readings) + "\n";
    for (const auto& s : r.steps)
        t += "step " + std::to_string(s.step) + " +" + s.added + " nrmse " + std::to_string(s.nrmse_before) + " -> " +
             std::to_string(s.nrmse_after) + " dBIC " + std::to_string(s.delta_bic) + " n_eff " +
             std::to_string(s.n_effective) + "\n";
    for (const auto& cd : r.candidates)
        t += "  step " + std::to_string(cd.step) + " " + cd.effect + " score " + std::to_string(cd.signature_score) +
             " dBIC " + std::to_string(cd.delta_bic_vs_base) + " " + cd.note + "\n";
    for (const auto& p : r.parameters) t += "  " + p.name + " = " + std::to_string(p.value) + " +- " + std::to_string(p.std) + "\n";
    t += "  base model alone:";
    for (const auto& p : r.base_parameters) t += " " + p.name + " = " + std::to_string(p.value);
    t += "\n";
    return t;
}

}  // namespace

TEST_CASE("DEM data: hidden rolling resistance is named and the error at least halved", "[diagnose][dem][slow]") {
    const auto c = run_case({{Effect::RollingResistance, {0.25}}});
    const auto& r = c.report;
    UNSCOPED_INFO(describe(c));
    CHECK(r.chosen_effect == "rolling_resistance");
    CHECK(r.nrmse_after <= 0.5 * r.nrmse_before);
    auto step = std::find_if(r.steps.begin(), r.steps.end(), [](auto& s) { return s.added == "rolling_resistance"; });
    REQUIRE(step != r.steps.end());
    CHECK(step->nrmse_after <= 0.5 * step->nrmse_before);
    CHECK(step->delta_bic < -10.0);
    CHECK(r.runs_used <= 30);
    auto mu_r = std::find_if(r.parameters.begin(), r.parameters.end(), [](auto& p) { return p.name == "rolling_friction"; });
    REQUIRE(mu_r != r.parameters.end());
    CHECK(mu_r->value > 0.1);  // the size of the effect, not its exact value (mu trades with mu_r)
    WARN(describe(c));
}

TEST_CASE("DEM data: control (noise + seating, no effect) is not given a physical effect", "[diagnose][dem][slow]") {
    const auto c = run_case({});
    const auto& r = c.report;
    UNSCOPED_INFO(describe(c));
    for (const auto& e : r.effects) CHECK(is_test_artefact(*effect_from_name(e)));
    CHECK((r.chosen_effect == "unexplained" || r.chosen_effect == "seating_error"));
    CHECK(r.runs_used <= 30);
    // Always shown, so the measured figures can be read off the CI log.
    WARN(describe(c));
}

// Robustness checks run by hand (not in CI, ~2-3 min each):
//   ./build/tests/test_diagnose "[.dem-loop]" -s
// the truth away from the calibration's start (modulus x1.4, friction 0.5, bonds x0.5)
// and another lab packing.
TEST_CASE("DEM data, off-nominal truth: hidden rolling resistance", "[diagnose][dem][.dem-loop]") {
    const auto c = run_case({{Effect::RollingResistance, {0.25}}}, {1.4, 1.25, 0.5}, 13, 8, 4);
    WARN(describe(c));
    CHECK(c.report.chosen_effect == "rolling_resistance");
    CHECK(c.report.nrmse_after <= 0.5 * c.report.nrmse_before);
}

TEST_CASE("DEM data, off-nominal truth: control", "[diagnose][dem][.dem-loop]") {
    const auto c = run_case({}, {1.4, 1.25, 0.5}, 13, 8, 4);
    WARN(describe(c));
    for (const auto& e : c.report.effects) CHECK(is_test_artefact(*effect_from_name(e)));
}

// The CI cases with another lab/model packing pair (lab seed 13, model seed 17), CI options:
//   ./build/tests/test_diagnose "[.dem-seeds]" -s
TEST_CASE("DEM data (other packing pair): hidden rolling resistance", "[diagnose][dem][.dem-seeds]") {
    const auto c = run_case({{Effect::RollingResistance, {0.25}}}, {}, 13, 7, 4, 17);
    WARN(describe(c));
    CHECK(c.report.chosen_effect == "rolling_resistance");
    CHECK(c.report.nrmse_after <= 0.5 * c.report.nrmse_before);
    auto step = std::find_if(c.report.steps.begin(), c.report.steps.end(), [](auto& s) { return s.added == "rolling_resistance"; });
    REQUIRE(step != c.report.steps.end());
    CHECK(step->nrmse_after <= 0.5 * step->nrmse_before);
    CHECK(step->delta_bic < -10.0);
}

TEST_CASE("DEM data (other packing pair): control", "[diagnose][dem][.dem-seeds]") {
    const auto c = run_case({}, {}, 13, 7, 4, 17);
    WARN(describe(c));
    for (const auto& e : c.report.effects) CHECK(is_test_artefact(*effect_from_name(e)));
}
