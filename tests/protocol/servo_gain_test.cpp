// The creep holds' adaptive servo gain (engine/protocol/servo_gain.hpp): it must speed up a
// platen that closes its stress error too slowly (soft specimen near failure) and back off
// on overshoot, and never go below the base gain (stiff specimen: held as before).
#include <catch2/catch.hpp>

#include <cmath>

#include "engine/protocol/servo_gain.hpp"

using triax::protocol::AdaptiveServoGain;

// A platen on a linear spring of stiffness k (per base-gain unit): each chunk closes the
// share 0.2 k_base / k of the error times the boost, as the servo's gain law does.
static int chunks_to_close(double stiffness_ratio, bool adaptive, double tolerance = 0.002) {
    AdaptiveServoGain gain;
    double error = 1.0;
    for (int n = 1; n <= 100000; ++n) {
        const double boost = adaptive ? gain.update(error) : 1.0;
        error -= 0.2 * boost * error / stiffness_ratio;
        if (std::abs(error) < tolerance) return n;
    }
    return 100000;
}

TEST_CASE("adaptive servo gain closes a soft specimen's error many times faster", "[servo]") {
    // Tangent stiffness 1/20 of the assumed skeleton stiffness (near failure).
    const int fixed = chunks_to_close(20.0, false);
    const int adaptive = chunks_to_close(20.0, true);
    CHECK(fixed > 500);
    CHECK(adaptive * 5 < fixed);
}

TEST_CASE("adaptive servo gain stays stable and at the base gain on a stiff specimen", "[servo]") {
    // Stiffness as assumed: the fixed gain closes 20 % per chunk; the adaptive one must not
    // oscillate (an overshoot halves the boost) and must still converge.
    CHECK(chunks_to_close(1.0, true) <= chunks_to_close(1.0, false));
    // A specimen stiffer than assumed: 4x boost would overshoot; the error must still close.
    CHECK(chunks_to_close(0.15, true) < 1000);
}

TEST_CASE("adaptive servo gain halves on a sign change and never drops below 1", "[servo]") {
    AdaptiveServoGain g;
    CHECK(g.update(1.0) == 1.0);
    CHECK(g.update(0.9) == Approx(1.5));  // slow closing: grow
    CHECK(g.update(0.8) == Approx(2.25));
    CHECK(g.update(-0.5) == Approx(1.125));  // overshoot: halve
    CHECK(g.update(0.4) == Approx(1.0));     // never below the base gain
    CHECK(g.update(0.1) == Approx(1.0));     // fast closing: keep
}
