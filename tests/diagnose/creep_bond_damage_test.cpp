// The creep side of bond degradation (issue 6): with creep curves of a bonded specimen the
// effect has a second parameter, an extra bond-damage rate acting only in the creep holds
// (dem_forward_model.hpp). A DEM creep diagnosis costs hours per run, so the loop is checked
// on the analytic stand-in given the same two-parameter effect (analytic_triaxial_model.hpp,
// `creep_bond_damage`): creep data carrying extra bond damage that the diagnosis is not told
// about must be named as bond degradation and not as contact creep viscosity, whose creep
// signature is the nearest in the catalog; and the two signatures must rank each other's
// data apart.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "analytic_triaxial_model.hpp"
#include "engine/diagnose/diagnosis.hpp"
#include "server/io/diagnosis_verdict.hpp"
#include "synthetic_lab.hpp"

using namespace triax::diagnose;
using namespace triax::diagnose::testing;

namespace {

const std::vector<double> kTruth{30e6, 36.0, 10.0, 8e-4};

AnalyticTriaxialModel bonded_creep_model() {
    AnalyticConditions c;
    c.creep_bond_damage = true;
    return AnalyticTriaxialModel(c);
}

double score_of(const std::vector<CandidateResult>& ranked, const std::string& effect) {
    auto it = std::find_if(ranked.begin(), ranked.end(), [&](auto& c) { return c.effect == effect; });
    REQUIRE(it != ranked.end());
    return it->signature_score;
}

const CandidateResult& candidate(const DiagnosisReport& r, const std::string& effect) {
    auto it = std::find_if(r.candidates.begin(), r.candidates.end(), [&](auto& c) { return c.step == 1 && c.effect == effect; });
    REQUIRE(it != r.candidates.end());
    return *it;
}

std::string describe(const DiagnosisReport& r) {
    std::string t = triax::io::diagnosis_verdict(r) + "\n";
    for (const auto& c : r.candidates)
        t += "  step " + std::to_string(c.step) + " " + c.effect + " score " + std::to_string(c.signature_score) +
             " dBIC " + std::to_string(c.delta_bic_vs_base) + " " + c.note + "\n";
    for (const auto& s : r.steps)
        t += "  step " + std::to_string(s.step) + " +" + s.added + " nrmse " + std::to_string(s.nrmse_before) + " -> " +
             std::to_string(s.nrmse_after) + " dBIC " + std::to_string(s.delta_bic) + "\n";
    for (const auto& p : r.parameters) t += "  " + p.name + " = " + std::to_string(p.value) + " +- " + std::to_string(p.std) + "\n";
    return t;
}

}  // namespace

TEST_CASE("creep data with hidden extra bond damage: named as bond degradation, not contact viscosity",
          "[diagnose][loop][creep]") {
    const auto model = bonded_creep_model();
    // No grain breakage in shear (breakage index 0): the damage shows in the creep holds only.
    const LabDataset lab = make_synthetic_lab(model, {kTruth, {{Effect::BondDegradation, {0.0, 3.0}}}}, {});
    DiagnoseObserver quiet;
    const auto r = run_diagnosis(lab, model, analytic_method_options(), quiet);
    INFO(describe(r));
    CHECK(r.chosen_effect == "bond_degradation");
    auto step = std::find_if(r.steps.begin(), r.steps.end(), [](auto& s) { return s.added == "bond_degradation"; });
    REQUIRE(step != r.steps.end());
    CHECK(step->nrmse_after <= 0.5 * step->nrmse_before);
    CHECK(step->delta_bic < -10.0);
    // Contact viscosity competed in the same step: its signature did not match the residual
    // (score below the fitting threshold), or it was fitted and lost on BIC.
    const auto& visc = candidate(r, "contact_creep_viscosity");
    if (visc.fitted) CHECK(visc.delta_bic_vs_base > candidate(r, "bond_degradation").delta_bic_vs_base + 10.0);
    else CHECK(visc.signature_score < 0.5 * candidate(r, "bond_degradation").signature_score);
    auto damage = std::find_if(r.parameters.begin(), r.parameters.end(), [](auto& p) { return p.name == "extra_bond_damage_rate"; });
    REQUIRE(damage != r.parameters.end());
    CHECK(std::abs(damage->value - 3.0) <= 4.0 * damage->std + 0.1 * 3.0);
    auto index = std::find_if(r.parameters.begin(), r.parameters.end(), [](auto& p) { return p.name == "breakage_index"; });
    REQUIRE(index != r.parameters.end());
    CHECK(index->value <= 0.1 * 2.0);  // no breakage in shear was put in, none taken out
}

TEST_CASE("creep signatures of extra bond damage and of contact viscosity rank each other's data apart",
          "[diagnose][loop][creep]") {
    const auto model = bonded_creep_model();
    SyntheticLabOptions lo;
    lo.seating_strain = 0.0;
    DiagnoseObserver quiet;
    // Data with one effect put in: its signature (both parameters at their nominal, as the
    // loop takes it) ranks first, the other's scores much less.
    const auto check_ranked_apart = [&](const std::pair<Effect, std::vector<double>>& put_in, const std::string& winner,
                                        const std::string& loser) {
        const LabDataset data = make_synthetic_lab(model, {kTruth, {put_in}}, lo);
        const auto ranked = rank_effects(data, model, kTruth, DiagnoseOptions{}, quiet);
        INFO(winner << " data: " << winner << " " << score_of(ranked, winner) << ", " << loser << " "
                    << score_of(ranked, loser));
        CHECK(ranked.front().effect == winner);
        CHECK(score_of(ranked, loser) < 0.7 * score_of(ranked, winner));
    };
    check_ranked_apart({Effect::BondDegradation, {0.0, 3.0}}, "bond_degradation", "contact_creep_viscosity");
    check_ranked_apart({Effect::ContactCreepViscosity, {0.004, 5000.0}}, "contact_creep_viscosity", "bond_degradation");
}
