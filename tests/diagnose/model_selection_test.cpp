// Effective readings and BIC.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "engine/diagnose/model_selection.hpp"
#include "engine/diagnose/residuals.hpp"

using namespace triax::diagnose;

TEST_CASE("white noise keeps nearly every reading, a smooth misfit keeps few", "[diagnose][bic]") {
    std::mt19937_64 rng(3);
    std::normal_distribution<double> nd;
    std::vector<double> white(2000), smooth(2000);
    for (std::size_t i = 0; i < white.size(); ++i) {
        white[i] = nd(rng);
        smooth[i] = std::sin(static_cast<double>(i) / 300.0);
    }
    CHECK(effective_readings(white) == Approx(2000.0).epsilon(0.1));
    CHECK(effective_readings(smooth) < 60.0);  // rho1 clamped at 0.95: n / 39
}

TEST_CASE("AR(1) residual: n_eff follows n (1 - rho) / (1 + rho)", "[diagnose][bic]") {
    std::mt19937_64 rng(5);
    std::normal_distribution<double> nd;
    std::vector<double> r(20000);
    double x = 0;
    for (auto& v : r) v = x = 0.5 * x + nd(rng);
    CHECK(effective_readings(r) == Approx(20000.0 / 3.0).epsilon(0.05));
    // Per series: two halves sum to about the whole.
    const double split = effective_readings(r, {{0, 10000}, {10000, 20000}});
    CHECK(split == Approx(20000.0 / 3.0).epsilon(0.05));
}

TEST_CASE("BIC rewards a real improvement and charges each parameter ln(n_eff)", "[diagnose][bic]") {
    const double b0 = bic(10.0, 100, 50.0, 3);
    CHECK(b0 == Approx(50.0 * std::log(0.1) + 3 * std::log(50.0)));
    // Same fit, one more parameter: worse by ln(n_eff).
    CHECK(bic(10.0, 100, 50.0, 4) - b0 == Approx(std::log(50.0)));
    // Halving RSS with one more parameter: better.
    CHECK(bic(5.0, 100, 50.0, 4) < b0);
    CHECK_THROWS(bic(1.0, 0, 1.0, 1));
    CHECK(std::isfinite(bic(0.0, 10, 5.0, 1)));
}

TEST_CASE("gains by confining pressure: per pressure RMS without minus with, unreached readings left out",
          "[diagnose][bic]") {
    // Two pressures, two series each (q and volumetric); residuals already normalised.
    const std::vector<std::pair<std::size_t, std::size_t>> ranges{{0, 2}, {2, 4}, {4, 6}, {6, 8}};
    const std::vector<double> pressure{100e3, 100e3, 50e3, 50e3};
    const std::vector<double> without{0.3, 0.3, 0.3, 0.3, 0.1, 0.1, 0.1, kUnreachedPenalty};
    const std::vector<double> with{0.1, 0.1, 0.1, 0.1, 0.2, 0.2, 0.2, 0.0};
    const auto g = gains_by_confining(without, with, ranges, pressure);
    REQUIRE(g.size() == 2);
    CHECK(g[0].first == 50e3);   // ascending pressure
    CHECK(g[0].second == Approx(0.1 - 0.2));  // the unreached reading is left out of both
    CHECK(g[1].first == 100e3);
    CHECK(g[1].second == Approx(0.3 - 0.1));
    CHECK_THROWS(gains_by_confining(without, with, ranges, {100e3}));
}

TEST_CASE("smallest nameable gain: the median spread of paired gains over two or more packings", "[diagnose][bic]") {
    CHECK(median_paired_spread({}) == 0.0);
    CHECK(median_paired_spread({{0.05}}) == 0.0);  // one packing has no spread
    // Spreads 0.01, 0.02 and 0.04 (sample SDs of evenly spaced triples): the median is 0.02.
    CHECK(median_paired_spread({{0.01, 0.02, 0.03}, {0.0, 0.02, 0.04}, {0.0, 0.04, 0.08}, {0.3}}) == Approx(0.02));
    CHECK(median_paired_spread({{0.01, 0.02, 0.03}, {0.0, 0.02, 0.04}}) == Approx(0.015));
}

// The outside suite's artefact steps (YADE data, docs/diagnosis.md section 10), as the
// reports stored them: the real ones are named, the corrections that stood in for the
// shape of YADE's rolling resistance are not, though their paired gains are as consistent.
TEST_CASE("artefact naming on the outside suite's figures: BIC beyond 6, paired, every pressure", "[diagnose][bic]") {
    // membrane (K_m 240 kPa), three pressures
    CHECK(artefact_named(-6.54, {0.0237, 0.0368, 0.0329}, {{50e3, 0.0509}, {100e3, 0.0187}, {200e3, 0.0133}}));
    // seating (0.5 % closure)
    CHECK(artefact_named(-14.83, {0.0516, 0.0604, 0.0175}, {{50e3, 0.0567}, {100e3, 0.0886}, {200e3, 0.0111}}));
    // rolling_strong's seating correction and rolling_weak's membrane correction: stand-ins
    CHECK_FALSE(artefact_named(-2.39, {0.0193, 0.0083, 0.0167}, {{50e3, 0.0223}, {100e3, 0.0175}}));
    CHECK_FALSE(artefact_named(-0.43, {0.0172, 0.0216, 0.0279}, {{100e3, 0.0172}}));
    // plain_loose's membrane: BIC beyond 6 but a paired gain within its spread
    CHECK_FALSE(artefact_named(-6.68, {0.1046, -0.0706, 0.0165}, {{100e3, 0.1046}}));
    // Strong and paired, but worse at one pressure: not an apparatus artefact.
    CHECK_FALSE(artefact_named(-14.83, {0.0516, 0.0604, 0.0175}, {{50e3, 0.0567}, {100e3, 0.0886}, {200e3, -0.002}}));
}
