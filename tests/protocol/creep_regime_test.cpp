// The regime flags read from a stage's curve (engine/protocol/creep_regime.hpp), on curves
// of known shape: primary creep decaying like ln(1 + t/tau) converges; primary creep with
// an accelerating term whose rate passes a minimum and rises is tertiary; a burst that dies
// out, reading noise and creep below the reading resolution are not; steady creep is
// neither settled nor tertiary; a jump larger than the loading step is a collapse.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>

#include "engine/protocol/creep_regime.hpp"

using namespace triax::protocol;

namespace {
constexpr double kStage = 60.0 * 3600.0;  // s
constexpr double kHeight = 0.2;           // the paper's specimen (m)
constexpr double kHour = 3600.0;

// A stage whose creep after the loading step (instant_mm) is creep_mm(t), read 12 times per
// fifth of the stage (the lab's readings).
CreepStageResult stage_from(double instant_mm, const std::function<double(double)>& creep_mm) {
    CreepStageResult st;
    for (int k = 0; k <= 60; ++k) {
        const double t = k * kStage / 60.0;
        const double d = (instant_mm + creep_mm(t)) * 1e-3;
        st.translated.push_back({t, d, d / kHeight});
    }
    st.instant_deformation_m = st.translated.front().axial_deformation_m;
    st.final_deformation_m = st.translated.back().axial_deformation_m;
    return st;
}

CreepRegime flags(double instant_mm, const std::function<double(double)>& creep_mm) {
    return classify_creep_regime(stage_from(instant_mm, creep_mm), kStage);
}

// Primary (transient) creep: c ln(1 + t / tau), its rate c / (tau + t) decays throughout.
std::function<double(double)> primary(double c_mm, double tau_s) {
    return [=](double t) { return c_mm * std::log1p(t / tau_s); };
}

// Primary creep plus an accelerating term a (t/T)^6: the rate falls to a minimum, then rises.
std::function<double(double)> primary_then_tertiary(double c_mm, double a_mm) {
    return [=](double t) { return c_mm * std::log1p(t / (0.5 * kHour)) + a_mm * std::pow(t / kStage, 6); };
}
}  // namespace

TEST_CASE("creep whose rate decays throughout converges and is not tertiary", "[protocol][regime]") {
    const auto r = flags(0.3, primary(0.1, 0.5 * kHour));
    CHECK(r.converged);
    CHECK_FALSE(r.accelerating);
}

TEST_CASE("creep whose rate passes a minimum and rises is tertiary", "[protocol][regime]") {
    const auto r = flags(0.3, primary_then_tertiary(0.1, 2.0));
    CHECK(r.accelerating);
    CHECK_FALSE(r.converged);
    // Fastest in the fourth fifth and still above the minimum in the fifth (a shear band
    // that slowed but kept going) is tertiary too: the minimum is taken over fifths 2-4.
    const auto band = flags(0.3, [](double t) {
        return 0.1 * std::log1p(t / (0.5 * kHour)) + 4.0 / (1.0 + std::exp(-(t - 0.75 * kStage) / (0.04 * kStage)));
    });
    CHECK(band.accelerating);
}

TEST_CASE("a burst that dies out is not tertiary, and the stage settles", "[protocol][regime]") {
    // Primary creep plus a 3-mm rearrangement in the middle of the stage, then quiet.
    const auto r = flags(5.0, [](double t) {
        return 0.1 * std::log1p(t / (0.5 * kHour)) + 3.0 / (1.0 + std::exp(-(t - 0.5 * kStage) / (0.02 * kStage)));
    });
    CHECK_FALSE(r.accelerating);
    CHECK(r.converged);
}

TEST_CASE("late creep faster than the slowest fifth but a small share of the stage's creep is noise", "[protocol][regime]") {
    // Strong primary creep, then 0.02 mm of extra creep spread over the last fifth: faster
    // than the fourth fifth, under 5 % of the stage's creep.
    const auto r = flags(0.4, [](double t) {
        return 0.12 * std::log1p(t / (0.01 * kHour)) + (t > 0.8 * kStage ? 0.02 * (t - 0.8 * kStage) / (0.2 * kStage) : 0.0);
    });
    CHECK_FALSE(r.accelerating);
    CHECK(r.converged);
}

TEST_CASE("a stage that ran away is accelerating whatever its curve", "[protocol][regime]") {
    auto ran_away = stage_from(0.5, primary(0.1, 0.5 * kHour));
    ran_away.ruptured = true;
    const auto r = classify_creep_regime(ran_away, kStage);
    CHECK(r.accelerating);
    CHECK_FALSE(r.converged);
}

TEST_CASE("a creep jump larger than the stage's loading step is a collapse (rupture)", "[protocol][regime]") {
    // The held load found no equilibrium near the current strain: 10 mm in one increment
    // after a loading step of 0.4 mm.
    CHECK(creep_collapse(10.0e-3, 0.4e-3));
    // Fast creep that is a fraction of the loading step is creep, not a collapse.
    CHECK_FALSE(creep_collapse(0.35e-3, 2.8e-3));
    // Equal is not more; a stage with no loading step has no scale to collapse against.
    CHECK_FALSE(creep_collapse(1e-3, 1e-3));
    CHECK_FALSE(creep_collapse(1e-3, 0.0));
}

TEST_CASE("creep below the reading resolution neither speeds a stage up nor keeps it unsettled", "[protocol][regime]") {
    // A tertiary shape whose last fifth creeps 1.7 um on a 200-mm specimen: below a 0.01-mm
    // reading, so the lab sees a settled stage.
    const auto tiny = flags(0.2, primary_then_tertiary(2e-4, 2e-3));
    CHECK_FALSE(tiny.accelerating);
    CHECK(tiny.converged);
    // The same shape ten times larger is readable, and tertiary.
    const auto readable = flags(0.2, primary_then_tertiary(2e-3, 2e-2));
    CHECK(readable.accelerating);
    CHECK_FALSE(readable.converged);
}

TEST_CASE("steady readable creep is neither settled nor tertiary", "[protocol][regime]") {
    const auto r = flags(0.2, [](double t) { return 0.2 * t / kStage; });  // 0.04 mm per fifth
    CHECK_FALSE(r.accelerating);
    CHECK_FALSE(r.converged);
}
