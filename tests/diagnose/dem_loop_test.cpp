// The whole loop on lab data made by the ENGINE: a reduced DEM specimen with an effect
// switched on that the diagnosis is not told about, read like a lab, from ANOTHER packing
// than the one the diagnosis runs (tests/diagnose/dem_loop_cases.hpp). A change of the last
// bits of a trajectory (another CPU, compiler or -march) is a change of packing, so CI
// keeps only the cases that pass on every one of five lab:model packing pairs
// (`./build/bench/dem_loop_packings`, docs/diagnosis.md section 8.3): the control. The
// hidden rolling resistance (tag [.dem-rolling]) and grain crushing ([.dem-crush]) cases
// pass on fewer pairs and are run by hand, with their pass counts in the docs.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "tests/diagnose/dem_loop_cases.hpp"

using namespace triax::diagnose;
using namespace triax::diagnose::testing;
using triax::protocol::TestScheme;

namespace {

// Every failed rule in the log, and the case fails if there is one.
void check_rules(const std::vector<std::string>& failed) {
    for (const auto& f : failed) UNSCOPED_INFO("failed: " << f);
    CHECK(failed.empty());
}

}  // namespace

TEST_CASE("DEM data: hidden rolling resistance is named and the error at least halved", "[diagnose][dem][.dem-rolling]") {
    const auto c = run_case(rolling_case());
    UNSCOPED_INFO(describe(c));
    check_rules(rolling_failures(c));
    WARN(describe(c));
}

TEST_CASE("DEM data: control (noise + seating, no effect) is not given a physical effect", "[diagnose][dem][slow]") {
    const auto c = run_case(control_case());
    UNSCOPED_INFO(describe(c));
    check_rules(control_failures(c));
    // Always shown, so the measured figures can be read off the CI log.
    WARN(describe(c));
}

// Run by hand (10-13 min of one core; it kept CI above its budget):
//   ./build/tests/test_diagnose "[.dem-crush]" -s
TEST_CASE("DEM data: hidden grain crushing at 50 and 200 kPa is named as grain breakage", "[diagnose][dem][.dem-crush]") {
    const auto c = run_case(crushing_case());
    UNSCOPED_INFO(describe(c));
    check_rules(crushing_failures(c));
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
    CaseSpec cs = crushing_case();
    cs.lab_seed = 7, cs.model_seed = 11;
    const auto c = run_case(cs);
    WARN(describe(c));
    check_rules(crushing_failures(c));
}

// The floor of the crushing case on a packing pair: the NRMSE of the TRUE model (nominal
// base, crushability 0.75) run on the model's packing against the lab made on the other
// packing, seating profiled on a grid (membrane 0, as in the lab). If this floor is above
// half the base model's misfit, no calibration can cut the error by 50 % on that pair.
//   ./build/tests/test_diagnose "[.dem-crush-floor]" -s
TEST_CASE("DEM data: floor of the crushing case at the true parameters, both packing pairs", "[diagnose][dem][.dem-crush-floor]") {
    for (auto [lab_seed, model_seed] : {std::pair<std::uint64_t, std::uint64_t>{7, 11}, {13, 17}}) {
        CaseSpec cs = crushing_case();
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
