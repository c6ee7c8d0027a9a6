// The loop on synthetic lab data made by a cheap analytic forward model with a hidden
// effect, measurement noise and a seating offset: it must name the effect and cut the
// error by at least half; a control dataset must not be given a physical effect.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "analytic_triaxial_model.hpp"
#include "engine/diagnose/diagnosis.hpp"
#include "engine/diagnose/model_evaluator.hpp"
#include "server/io/diagnosis_json.hpp"
#include "server/io/diagnosis_verdict.hpp"
#include "synthetic_lab.hpp"

using namespace triax::diagnose;
using namespace triax::diagnose::testing;

namespace {

struct Recorder : DiagnoseObserver {
    int progress_calls = 0, candidates = 0;
    double last_pct = 0;
    bool cancel = false;
    void on_progress(double pct, std::string_view) override { ++progress_calls, last_pct = pct; }
    void on_candidate(const CandidateResult&) override { ++candidates; }
    bool cancelled() const override { return cancel; }
};

const std::vector<double> kTruth{30e6, 36.0, 10.0, 8e-4};

DiagnosisReport diagnose(const std::vector<std::pair<Effect, std::vector<double>>>& hidden, SyntheticLabOptions lab_opt = {},
                         DiagnoseOptions opt = analytic_method_options()) {
    AnalyticTriaxialModel model;
    const LabDataset lab = make_synthetic_lab(model, {kTruth, hidden}, lab_opt);
    Recorder rec;
    auto rep = run_diagnosis(lab, model, opt, rec);
    CHECK(rec.progress_calls > 0);
    CHECK(rec.last_pct == Approx(100.0));
    CHECK(rec.candidates > 0);
    return rep;
}

// The error cut attributable to the effect alone: the step that added it, against the
// model entering that step (already corrected for seating if seating was found first).
void check_step_cut(const DiagnosisReport& r, std::string_view effect) {
    auto it = std::find_if(r.steps.begin(), r.steps.end(), [&](auto& s) { return s.added == effect; });
    REQUIRE(it != r.steps.end());
    CHECK(it->nrmse_after <= 0.5 * it->nrmse_before);
    CHECK(it->delta_bic < -10.0);
    CHECK(r.nrmse_after <= 0.5 * r.nrmse_before);
}

// The fitted value of a hidden parameter must agree with the truth within its reported
// uncertainty (4 sigma, plus 3 % for the seating form the diagnosis does not share).
void check_parameter(const DiagnosisReport& r, std::string_view name, double truth) {
    auto it = std::find_if(r.parameters.begin(), r.parameters.end(), [&](auto& p) { return p.name == name; });
    REQUIRE(it != r.parameters.end());
    CHECK(it->std > 0.0);
    CHECK(std::abs(it->value - truth) <= 4.0 * it->std + 0.03 * std::abs(truth));
}

void describe(const DiagnosisReport& r) {
    std::string text = triax::io::diagnosis_verdict(r) + "\n";
    for (const auto& c : r.candidates)
        text += "  step " + std::to_string(c.step) + " " + c.effect + " score " + std::to_string(c.signature_score) + " dBIC " +
                std::to_string(c.delta_bic_vs_base) + " " + c.note + "\n";
    for (const auto& s : r.steps)
        text += "  step " + std::to_string(s.step) + " +" + s.added + " nrmse " + std::to_string(s.nrmse_before) + " -> " +
                std::to_string(s.nrmse_after) + " dBIC " + std::to_string(s.delta_bic) + "\n";
    for (const auto& p : r.parameters) text += "  " + p.name + " = " + std::to_string(p.value) + " +- " + std::to_string(p.std) + "\n";
    for (const auto& e : r.error_after)
        if (e.phase == "all") text += "  " + e.curve + " NRMSE " + std::to_string(e.nrmse) + "\n";
    UNSCOPED_INFO(text);
}

}  // namespace

TEST_CASE("control dataset (noise + seating only) is not given a physical effect", "[diagnose][loop]") {
    const auto r = diagnose({});
    describe(r);
    for (const auto& e : r.effects) CHECK(is_test_artefact(*effect_from_name(e)));
    CHECK(r.outcome != Outcome::Unexplained);
    CHECK((r.chosen_effect == "none" || r.chosen_effect == "seating_error"));
    CHECK(r.n_effective > 10.0);
    CHECK(r.n_effective <= r.n_readings);
    CHECK(!r.error_before.empty());
    check_parameter(r, "young_modulus_at_100kPa", 30e6);
    check_parameter(r, "creep_log_time_coefficient", 8e-4);
}

TEST_CASE("hidden bond degradation is named and the error at least halved", "[diagnose][loop]") {
    const auto r = diagnose({{Effect::BondDegradation, {1.0}}});
    describe(r);
    CHECK(r.chosen_effect == "bond_degradation");
    check_step_cut(r, "bond_degradation");
    check_parameter(r, "breakage_index", 1.0);
    check_parameter(r, "friction_angle", 36.0);
    CHECK(r.delta_bic_vs_base < -10.0);
}

TEST_CASE("hidden rolling resistance is named and the error at least halved", "[diagnose][loop]") {
    const auto r = diagnose({{Effect::RollingResistance, {0.2}}});
    describe(r);
    CHECK(r.chosen_effect == "rolling_resistance");
    check_step_cut(r, "rolling_resistance");
    check_parameter(r, "rolling_friction", 0.2);
}

TEST_CASE("hidden contact creep viscosity is named and the error at least halved", "[diagnose][loop]") {
    const auto r = diagnose({{Effect::ContactCreepViscosity, {0.004, 5000.0}}});
    describe(r);
    CHECK(r.chosen_effect == "contact_creep_viscosity");
    check_step_cut(r, "contact_creep_viscosity");
    check_parameter(r, "viscous_strain", 0.004);
    check_parameter(r, "viscous_time", 5000.0);
}

TEST_CASE("hidden moisture bonding is named and the error at least halved", "[diagnose][loop]") {
    const auto r = diagnose({{Effect::MoistureBonding, {25e3}}});
    describe(r);
    CHECK(r.chosen_effect == "moisture_bonding");
    check_step_cut(r, "moisture_bonding");
    check_parameter(r, "bond_cohesion", 25e3);
}

TEST_CASE("membrane compliance without seating is named as the artefact", "[diagnose][loop]") {
    SyntheticLabOptions lo;
    lo.seating_strain = 0.0;
    lo.membrane_stiffness_pa = 300e3;
    const auto r = diagnose({}, lo);
    describe(r);
    CHECK(r.chosen_effect == "membrane_compliance");
    check_step_cut(r, "membrane_compliance");
    check_parameter(r, "membrane_stiffness", 300e3);
}

// Lab = base model + a misfit of a shape nothing in the catalog produces, above the
// unexplained floor (kUnexplainedFloor, 5 % of a curve's range pooled, 10 % in a phase).
LabDataset lab_with_outside_misfit(double q_amplitude, double creep_step) {
    AnalyticTriaxialModel model;
    SyntheticLabOptions lo;
    lo.seating_strain = 0.0;
    LabDataset lab = make_synthetic_lab(model, {kTruth, {}}, lo);
    for (auto& c : lab.curves) {
        if (c.kind == CurveKind::Shear)
            for (std::size_t i = 0; i < c.deviator_pa.size(); ++i)
                c.deviator_pa[i] *= 1.0 + q_amplitude * std::sin(2 * M_PI * c.axial_strain[i] / 0.03);
        else
            for (std::size_t i = 0; i < c.axial_strain.size(); ++i)
                if (c.time_s[i] > 12000.0) c.axial_strain[i] += creep_step * c.stress_level;
    }
    return lab;
}

TEST_CASE("a misfit outside the catalog is reported as unexplained with where it remains", "[diagnose][loop]") {
    // A stick-slip-like oscillation of q (+-15 % of q, period 3 % strain) and a creep step at
    // 200 min.
    AnalyticTriaxialModel model;
    const LabDataset lab = lab_with_outside_misfit(0.15, 1e-3);
    Recorder rec;
    const auto r = run_diagnosis(lab, model, analytic_method_options(), rec);
    describe(r);
    CHECK(r.outcome == Outcome::Unexplained);
    CHECK(r.chosen_effect == "unexplained");
    CHECK_THAT(triax::io::diagnosis_verdict(r), Catch::Contains("unexplained") && Catch::Contains("largest in"));
    CHECK(r.n_effective < 0.6 * r.n_readings);  // structured residual: readings are correlated
}

TEST_CASE("a small misfit of another model family is no effect, not unexplained", "[diagnose][loop]") {
    // The same shapes at +-3 % of q: below the floor a plain material is left alone.
    AnalyticTriaxialModel model;
    const LabDataset lab = lab_with_outside_misfit(0.03, 1e-4);
    Recorder rec;
    const auto r = run_diagnosis(lab, model, analytic_method_options(), rec);
    describe(r);
    CHECK(r.outcome == Outcome::NoEffectNeeded);
    CHECK(r.chosen_effect == "none");
    CHECK_THAT(triax::io::diagnosis_verdict(r), Catch::StartsWith("no effect needed"));
}

// A model that cannot show one catalog effect on the given data (as the DEM's grain
// breakage on shear-only data): the effect is never a candidate and the verdict says it
// was not testable, so "no effect found" is not read as "no breakage".
struct WithoutBondDegradation final : ForwardModel {
    AnalyticTriaxialModel inner;
    std::vector<ParameterSpec> base_parameters() const override { return inner.base_parameters(); }
    std::vector<ParameterSpec> effect_parameters(Effect e) const override {
        return e == Effect::BondDegradation ? std::vector<ParameterSpec>{} : inner.effect_parameters(e);
    }
    LabDataset simulate(const ModelPoint& p, std::uint64_t seed) const override { return inner.simulate(p, seed); }
};

TEST_CASE("an effect the model cannot show on the data is not offered, and the verdict says so", "[diagnose][loop]") {
    WithoutBondDegradation model;
    const LabDataset lab = make_synthetic_lab(model.inner, {kTruth, {}}, {});
    DiagnoseOptions opt = analytic_method_options();
    opt.budget_runs = 12;
    opt.refine_runs = 4;
    Recorder rec;
    const auto r = run_diagnosis(lab, model, opt, rec);
    for (const auto& c : r.candidates) CHECK(c.effect != "bond_degradation");
    REQUIRE(!r.not_testable.empty());
    CHECK(r.not_testable.front().effect == "bond_degradation");
    CHECK_THAT(triax::io::diagnosis_verdict(r), Catch::Contains("not tested: bond_degradation"));
}

// The report depends on the method's options (batch_runs among them) and the seed, never
// on how many evaluations run at once.
TEST_CASE("concurrent evaluations: the same report for concurrency 1 and 3", "[diagnose][loop]") {
    AnalyticTriaxialModel model;
    const LabDataset lab = make_synthetic_lab(model, {kTruth, {{Effect::RollingResistance, {0.2}}}}, {});
    DiagnoseOptions opt = analytic_method_options();
    opt.batch_runs = 2;
    opt.concurrency = 1;
    Recorder a, b;
    const auto r1 = run_diagnosis(lab, model, opt, a);
    opt.concurrency = 3;
    const auto r2 = run_diagnosis(lab, model, opt, b);
    CHECK(r1.chosen_effect == "rolling_resistance");
    CHECK(triax::io::diagnosis_report_to_json(r1).dump() == triax::io::diagnosis_report_to_json(r2).dump());
}

TEST_CASE("cancellation stops the loop with DiagnosisCancelled", "[diagnose][loop]") {
    AnalyticTriaxialModel model;
    const LabDataset lab = make_synthetic_lab(model, {kTruth, {}}, {});
    Recorder rec;
    rec.cancel = true;
    CHECK_THROWS_AS(run_diagnosis(lab, model, analytic_method_options(), rec), DiagnosisCancelled);
}

TEST_CASE("bad options are rejected before any run", "[diagnose][loop]") {
    AnalyticTriaxialModel model;
    const LabDataset lab = make_synthetic_lab(model, {kTruth, {}}, {});
    Recorder rec;
    DiagnoseOptions opt = analytic_method_options();
    opt.budget_runs = 2;
    CHECK_THROWS_WITH(run_diagnosis(lab, model, opt, rec), Catch::Contains("budget_runs"));
    CHECK(rec.progress_calls == 0);
}

TEST_CASE("rank_effects at the true base point puts the hidden effect first", "[diagnose][loop]") {
    AnalyticTriaxialModel model;
    SyntheticLabOptions lo;
    lo.seating_strain = 0.0;
    const LabDataset lab = make_synthetic_lab(model, {kTruth, {{Effect::BondDegradation, {1.0}}}}, lo);
    Recorder rec;
    const auto ranked = rank_effects(lab, model, kTruth, DiagnoseOptions{}, rec);
    REQUIRE(ranked.size() == 6);
    CHECK(ranked.front().effect == "bond_degradation");
    CHECK(ranked.front().signature_score > 0.4);
    CHECK(ranked[1].signature_score < ranked.front().signature_score);
    CHECK_THROWS_WITH(rank_effects(lab, model, {1.0}, DiagnoseOptions{}, rec), Catch::Contains("base values"));
}

// A model whose runs fail on the calibration's packing over part of the parameter box (as a
// 150-grain DEM specimen loses a particle through its membrane): the point is run again on
// another packing, counted, and never scored as a total misfit.
struct FailsOnFirstPacking final : ForwardModel {
    AnalyticTriaxialModel inner;
    std::vector<ParameterSpec> base_parameters() const override { return inner.base_parameters(); }
    std::vector<ParameterSpec> effect_parameters(Effect e) const override { return inner.effect_parameters(e); }
    LabDataset simulate(const ModelPoint& p, std::uint64_t seed) const override {
        if (seed < kRetrySeedOffset && p.base[1] > 37.0) throw std::runtime_error("particle 65 escaped the domain box");
        return inner.simulate(p, seed);
    }
};

TEST_CASE("a run that fails is retried on another packing and reported, not scored as a misfit", "[diagnose][loop]") {
    FailsOnFirstPacking model;
    const LabDataset lab = make_synthetic_lab(model.inner, {kTruth, {}}, {});
    DiagnoseOptions opt = analytic_method_options();
    opt.budget_runs = 12;
    opt.refine_runs = 4;
    Recorder rec;
    const auto r = run_diagnosis(lab, model, opt, rec);
    describe(r);
    CHECK(r.retried_runs > 0);
    CHECK(r.failed_runs == 0);
    CHECK(r.outcome != Outcome::Unexplained);
    CHECK_THAT(triax::io::diagnosis_verdict(r), Catch::Contains("retried on another packing"));
}

TEST_CASE("the noise floor is measured on other packings and stated", "[diagnose][loop]") {
    // The analytic model does not depend on the packing: its floor is 0 and the tolerance
    // is the lab's reading noise, which the synthetic lab sets.
    AnalyticTriaxialModel model;
    SyntheticLabOptions lo;
    const LabDataset lab = make_synthetic_lab(model, {kTruth, {}}, lo);
    DiagnoseOptions opt = analytic_method_options();
    opt.budget_runs = 8;
    opt.refine_runs = 2;
    opt.max_effects = 1;
    Recorder rec;
    const auto r = run_diagnosis(lab, model, opt, rec);
    CHECK(r.noise.seeds == opt.noise_seeds);
    CHECK(r.noise.model_nrmse == Approx(0.0).margin(1e-6));
    CHECK(r.noise.lab_nrmse > 0.0);
    CHECK(r.noise.tolerance_nrmse == Approx(r.noise.lab_nrmse).margin(1e-5));
    CHECK_THAT(triax::io::diagnosis_verdict(r), Catch::Contains("noise floor"));
}
