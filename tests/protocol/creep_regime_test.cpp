// The regime flags read from a stage's curve: tertiary = the rate passes a minimum and rises.
#include <catch2/catch.hpp>

#include <vector>

#include "engine/protocol/creep_regime.hpp"

using namespace triax::protocol;

namespace {
constexpr double kStage = 60.0 * 3600.0;
constexpr double kHeight = 0.2;  // the paper's specimen (m)

// A stage of 60 h on the 200-mm specimen whose curve is the loading step, then `per_fifth`
// mm of creep in each fifth, spread evenly over 12 readings per fifth (the lab's readings).
CreepStageResult stage_with_fifths(double instant_mm, const std::vector<double>& per_fifth_mm) {
    CreepStageResult st;
    double d = instant_mm * 1e-3;
    st.translated.push_back({0.0, d, d / kHeight});
    for (int f = 0; f < 5; ++f)
        for (int i = 1; i <= 12; ++i) {
            d += per_fifth_mm[f] * 1e-3 / 12.0;
            st.translated.push_back({(f + i / 12.0) * kStage / 5.0, d, d / kHeight});
        }
    st.instant_deformation_m = st.translated.front().axial_deformation_m;
    st.final_deformation_m = st.translated.back().axial_deformation_m;
    return st;
}

// Both flags of the stage with these fifths.
void check_flags(double instant_mm, const std::vector<double>& per_fifth_mm, bool accelerating, bool converged) {
    const auto r = classify_creep_regime(stage_with_fifths(instant_mm, per_fifth_mm), kStage);
    CHECK(r.accelerating == accelerating);
    CHECK(r.converged == converged);
}
}  // namespace

TEST_CASE("a stage whose creep rate passes a minimum and rises is tertiary", "[protocol][regime]") {
    // Group A at S = 0.8 (session 12): fastest in the fourth fifth, still fast in the fifth.
    const auto a = classify_creep_regime(stage_with_fifths(0.29, {0.12, 0.08, 0.41, 4.34, 2.04}), kStage);
    CHECK(a.accelerating);
    CHECK_FALSE(a.converged);
    // Group B seed 1: speeds up over the last three fifths.
    const auto b = classify_creep_regime(stage_with_fifths(0.50, {0.81, 0.14, 0.15, 0.26, 0.59}), kStage);
    CHECK(b.accelerating);
}

TEST_CASE("decaying creep converges, late bursts that die out are not tertiary", "[protocol][regime]") {
    // Primary creep decaying like a log: converged.
    check_flags(0.27, {30.0, 5.0, 2.5, 1.6, 1.2}, false, true);
    // Group D at S = 0.8 (session 12): a burst in the third fifth, then it settles.
    check_flags(5.08, {3.01, 0.11, 0.40, 0.15, 0.01}, false, true);
}

TEST_CASE("reading noise on a converged stage does not raise the tertiary flag", "[protocol][regime]") {
    // The last fifth is twice the slowest earlier fifth, but holds under 5 % of the creep.
    check_flags(0.37, {4.0, 0.3, 0.1, 0.15, 0.2}, false, true);
}

TEST_CASE("a stage that ran away is accelerating whatever its curve", "[protocol][regime]") {
    auto ran_away = stage_with_fifths(0.5, {1.0, 0.5, 0.2, 0.1, 0.05});
    ran_away.ruptured = true;
    const auto r = classify_creep_regime(ran_away, kStage);
    CHECK(r.accelerating);
    CHECK_FALSE(r.converged);
}

TEST_CASE("a creep jump larger than the stage's loading step is a collapse (rupture)", "[protocol][regime]") {
    // Group D, preset micro with the cement neck at 0.6 (session 18): 9.65 mm in the hour
    // after 13.3 h at S = 0.8, after a loading step of 0.37 mm.
    CHECK(creep_collapse(9.65e-3, 0.366e-3));
    // Group C at S = 0.8 (same micro): its largest hourly creep, 0.35 mm, after a 2.83-mm
    // loading step, is accelerating creep, not a collapse.
    CHECK_FALSE(creep_collapse(0.35e-3, 2.83e-3));
    // Equal is not more; a stage with no loading step has no scale to collapse against.
    CHECK_FALSE(creep_collapse(1e-3, 1e-3));
    CHECK_FALSE(creep_collapse(1e-3, 0.0));
}

TEST_CASE("creep below the reading resolution neither speeds a stage up nor keeps it unsettled", "[protocol][regime]") {
    // Group D seed 5 at S = 0.6 (presets, session 19): the last fifth creeps 1.4 x the fourth,
    // but 2.3 um in 12 h on a 200-mm specimen is below a 0.01-mm reading.
    check_flags(0.2009, {0.0102, 0.0038, 0.0024, 0.0016, 0.0023}, false, true);
    // The same shape ten times larger is readable, and tertiary.
    check_flags(2.009, {0.102, 0.038, 0.024, 0.016, 0.023}, true, false);
    // Steady readable creep (group A seed 4 at S = 0.8, presets): neither settled nor tertiary.
    check_flags(0.2188, {0.036, 0.038, 0.039, 0.038, 0.017}, false, false);
}
