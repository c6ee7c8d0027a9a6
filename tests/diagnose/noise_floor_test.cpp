// The noise floor: the lab's reading noise from a curve's own readings, and the model's
// scatter between packings from replicate residuals.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "engine/diagnose/noise_floor.hpp"
#include "engine/diagnose/residuals.hpp"
#include "lab_fixtures.hpp"

using namespace triax::diagnose;
using namespace triax::diagnose::testing;

namespace {

// A smooth hardening curve (q rising to 300 kPa over 15 %) read 150 times with white noise.
LabDataset noisy_curve(double sigma_pa, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> nd(0.0, 1.0);
    std::vector<double> e, q;
    for (int i = 0; i <= 150; ++i) {
        const double eps = 0.001 * i;
        e.push_back(eps);
        q.push_back(300e3 * eps / (0.02 + eps) * 1.13 + sigma_pa * nd(rng));
    }
    LabDataset lab;
    lab.curves.push_back(shear_curve(100e3, e, q));
    return lab;
}

}  // namespace

TEST_CASE("lab reading noise: white noise on a smooth curve is recovered, the curve's shape is not noise", "[diagnose][noise]") {
    const auto quiet = residual_layout(noisy_curve(0.0, 1));
    CHECK(lab_reading_noise(quiet) < 0.002);  // curvature alone: well under 0.2 % of the range
    for (unsigned seed : {1u, 2u, 3u}) {
        const auto layout = residual_layout(noisy_curve(3000.0, seed));
        const double expected = 3000.0 / layout.front().scale;
        CHECK(lab_reading_noise(layout) == Approx(expected).epsilon(0.2));
    }
}

TEST_CASE("model scatter: the spread of replicate residuals, unreached readings and failed runs left out", "[diagnose][noise]") {
    const auto layout = residual_layout(noisy_curve(0.0, 1));
    const std::size_t n = layout.front().x.size();
    // Three packings: residuals -0.1, 0, +0.1 everywhere: sample std 0.1.
    std::vector<std::vector<double>> reps{std::vector<double>(n, -0.1), std::vector<double>(n, 0.0), std::vector<double>(n, 0.1)};
    reps[2][5] = 1.0;  // one reading not reached by the third packing: skipped
    reps.push_back({});  // a failed run: skipped
    const NoiseFloor f = noise_floor(layout, reps);
    CHECK(f.seeds == 3);
    CHECK(f.model_nrmse == Approx(0.1));
    REQUIRE(f.model_nrmse_per_curve.size() == 1);
    // One shear curve: its kind's scatter is the pooled one.
    REQUIRE(f.model_nrmse_per_kind.size() == 1);
    CHECK(f.model_nrmse_per_kind[0].first == "shear");
    CHECK(f.model_nrmse_per_kind[0].second == Approx(0.1));
    CHECK(f.tolerance_nrmse == Approx(std::sqrt(2.0 * 0.01 + f.lab_nrmse * f.lab_nrmse)));
    // A packing that runs away at some readings (a creep stage into tertiary creep, 50 lab
    // ranges off): each reading's variance is capped at one lab range squared, so the floor
    // stays a floor (here at most sqrt((n - 10) 0.01 + 10) / sqrt(n)).
    auto runaway = reps;
    for (std::size_t i = 0; i < 10; ++i) runaway[1][i] = 50.0;
    const NoiseFloor capped = noise_floor(layout, runaway);
    CHECK(capped.model_nrmse <= std::sqrt(((n - 10) * 0.01 + 10.0) / static_cast<double>(n)) + 1e-12);
    CHECK(capped.model_nrmse > f.model_nrmse);  // still wider than without the runaway
    // One packing only: no scatter can be measured, the tolerance is the lab's noise.
    const NoiseFloor one = noise_floor(layout, {std::vector<double>(n, 0.0)});
    CHECK(one.seeds == 1);
    CHECK(one.model_nrmse == 0.0);
}

TEST_CASE("curve kinds: creep stages and their instant series apart from the shear curves", "[diagnose][noise]") {
    CHECK(curve_kind("creep-3@100kPa") == "creep");
    CHECK(curve_kind("instant@50kPa") == "creep");
    CHECK(curve_kind("stress_strain@100kPa") == "shear");
    CHECK(curve_kind("volumetric@200kPa") == "shear");
}
