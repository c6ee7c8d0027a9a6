// Report <-> JSON: lab units at the edge, exact round trip, request validation.
#include <catch2/catch.hpp>

#include <algorithm>

#include "server/io/diagnosis_json.hpp"
#include "server/io/diagnosis_verdict.hpp"

using namespace triax::diagnose;
using triax::io::DiagnosisRequestError;

namespace {
DiagnosisReport sample_report() {
    DiagnosisReport r;
    r.chosen_effect = "bond_degradation";
    r.effects = {"seating_error", "bond_degradation"};
    r.parameters = {{"friction_angle", "deg", 36.0, 0.2}, {"breakage_index", "-", 1.0, 0.05}};
    r.base_parameters = {{"friction_angle", "deg", 34.0, 0.3}};
    r.error_before = {{"stress_strain@100kPa", "pre_peak", "Pa", 30, 2, 12000.0, 0.05},
                      {"creep-2@100kPa", "primary", "-", 10, 0, 2e-4, 0.1}};
    r.error_after = {{"stress_strain@100kPa", "pre_peak", "Pa", 30, 0, 1500.0, 0.006}};
    r.delta_bic_vs_base = -300.0;
    r.runners_up = {{"rolling_resistance", 40.0}};
    CandidateResult c;
    c.step = 2;
    c.effect = "bond_degradation";
    c.signature_score = 0.9;
    c.fitted = true;
    c.parameters = {{"breakage_index", "-", 1.0, 0.05}};
    c.delta_bic_vs_base = -280.0;
    r.candidates = {c};
    r.steps = {{1, "seating_error", 1.5, 0.2, -20.0, 300.0}, {2, "bond_degradation", 0.2, 0.02, -280.0, 400.0}};
    r.n_readings = 500;
    r.n_effective = 400;
    r.nrmse_before = 1.5;
    r.nrmse_after = 0.02;
    r.runs_used = 77;
    r.noise.model_nrmse_per_curve = {{"stress_strain@100kPa", 0.03}, {"creep-2@100kPa", 0.05}};
    r.fit_weights = {{"shear", 1.0}, {"creep", 0.08}};
    r.outcome = Outcome::EffectFound;
    return r;
}
}  // namespace

TEST_CASE("report JSON uses lab units and the API's field names", "[diagnose][json]") {
    const auto j = triax::io::diagnosis_report_to_json(sample_report());
    CHECK(j.at("chosen_effect") == "bond_degradation");
    CHECK(j.at("error_before")[0].at("unit") == "kPa");
    CHECK(j.at("error_before")[0].at("rmse").get<double>() == Approx(12.0));
    CHECK(j.at("error_before")[1].at("unit") == "%");
    CHECK(j.at("error_before")[1].at("rmse").get<double>() == Approx(0.02));
    CHECK(j.at("delta_bic").at("vs_base").get<double>() == Approx(-300.0));
    CHECK(j.at("delta_bic").at("runners_up")[0].at("effect") == "rolling_resistance");
    CHECK(j.at("parameters")[1].at("std").get<double>() == Approx(0.05));
    CHECK(j.at("candidates")[0].at("step") == 2);
}

TEST_CASE("report JSON reads back to the same report", "[diagnose][json]") {
    const auto r0 = sample_report();
    const auto r1 = triax::io::diagnosis_report_from_json(triax::io::diagnosis_report_to_json(r0));
    CHECK(r1.chosen_effect == r0.chosen_effect);
    CHECK(r1.effects == r0.effects);
    REQUIRE(r1.error_before.size() == 2);
    CHECK(r1.error_before[0].unit == "Pa");
    CHECK(r1.error_before[0].rmse == Approx(12000.0));
    CHECK(r1.error_before[1].unit == "-");
    CHECK(r1.error_before[1].rmse == Approx(2e-4));
    CHECK(r1.runners_up[0].delta_bic == Approx(40.0));
    CHECK(r1.steps.size() == 2);
    CHECK(r1.steps[1].added == "bond_degradation");
    CHECK(r1.candidates[0].parameters[0].name == "breakage_index");
    CHECK(r1.runs_used == 77);
    // Per-curve noise by label (a JSON object: the order is the labels').
    auto by_label = [](auto v) { std::sort(v.begin(), v.end()); return v; };
    CHECK(by_label(r1.noise.model_nrmse_per_curve) == by_label(r0.noise.model_nrmse_per_curve));
    CHECK(by_label(r1.fit_weights) == by_label(r0.fit_weights));
    CHECK(triax::io::diagnosis_verdict(r1) == triax::io::diagnosis_verdict(r0));
    CHECK(r1.outcome == r0.outcome);
}

TEST_CASE("diagnose request options are validated with the field named", "[diagnose][json]") {
    auto o = triax::io::diagnose_options_from_json({{"budget_runs", 30}, {"seed", 5}, {"scheme_id", 3}});
    CHECK(o.budget_runs == 30);
    CHECK(o.seed == 5u);
    CHECK(triax::io::diagnose_options_from_json(nlohmann::json::object()).budget_runs == DiagnoseOptions{}.budget_runs);
    CHECK(triax::io::diagnose_options_from_json(nlohmann::json()).refine_runs == DiagnoseOptions{}.refine_runs);
    try {
        triax::io::diagnose_options_from_json({{"budget_runs", 2}});
        FAIL("budget_runs = 2 was accepted");
    } catch (const DiagnosisRequestError& e) {
        CHECK(e.field == "/budget_runs");
        CHECK_THAT(e.what(), Catch::Contains("between 4 and 400"));
    }
    // The lab's relative density: % at the edge, a fraction inside; absent or null = not stated.
    CHECK_FALSE(triax::io::diagnose_options_from_json(nlohmann::json::object()).relative_density);
    CHECK_FALSE(triax::io::diagnose_options_from_json({{"relative_density_percent", nullptr}}).relative_density);
    const auto dr = triax::io::diagnose_options_from_json({{"relative_density_percent", 85}});
    REQUIRE(dr.relative_density);
    CHECK(*dr.relative_density == Approx(0.85));
    CHECK(triax::io::diagnose_options_to_json(dr)["relative_density_percent"].get<double>() == Approx(85.0));
    CHECK(triax::io::diagnose_options_to_json(o)["relative_density_percent"].is_null());
    try {
        triax::io::diagnose_options_from_json({{"relative_density_percent", 150}});
        FAIL("relative_density_percent = 150 was accepted");
    } catch (const DiagnosisRequestError& e) {
        CHECK(e.field == "/relative_density_percent");
        CHECK_THAT(e.what(), Catch::Contains("between 0.0 and 100.0"));
    }
    CHECK_THROWS_AS(triax::io::diagnose_options_from_json({{"seed", "one"}}), DiagnosisRequestError);
    CHECK_THROWS_AS(triax::io::diagnose_options_from_json({{"concurrency", 1.5}}), DiagnosisRequestError);
    CHECK_THROWS_AS(triax::io::diagnose_options_from_json(nlohmann::json::array()), DiagnosisRequestError);
}
