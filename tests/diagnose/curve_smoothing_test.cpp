// The DEM curve smoothing (curve_smoothing.hpp): a straight line stays straight, noise
// shrinks, the window grows with strain, and the start is kept.
#include "engine/diagnose/curve_smoothing.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace triax::diagnose;

TEST_CASE("smoothing over relative strain keeps lines and the start, and damps alternating noise", "[diagnose][smoothing]") {
    std::vector<double> x, line, noisy;
    for (int i = 0; i <= 75; ++i) {
        x.push_back(0.002 * i);  // 0 .. 15 % every 0.2 %
        line.push_back(3.0 + 200.0 * x.back());
        noisy.push_back(100.0 + (i % 2 ? 10.0 : -10.0));
    }
    const auto l = smooth_over_relative_strain(x, line);
    for (std::size_t i = 0; i < x.size(); ++i) {
        // Symmetric weights where the window is whole; near the start the window holds only
        // the reading itself, which is returned as it is.
        CHECK(l[i] == Approx(line[i]).margin(1e-9));
    }
    const auto s = smooth_over_relative_strain(x, noisy);
    CHECK(s[0] == noisy[0]);
    CHECK(s[1] == noisy[1]);                   // 0.2 %: the window (+-0.04 %) holds no neighbour
    CHECK(std::abs(s[50] - 100.0) < 1.0);      // 10 %: +-2 %, 19 readings
    CHECK(std::abs(s[75] - 100.0) < 2.0);      // 15 %: the window is cut at the last reading
    CHECK_THROWS(smooth_over_relative_strain({0.0, 1.0}, {1.0}));
}
