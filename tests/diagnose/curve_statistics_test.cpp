// The curve toolkit (curve_statistics.hpp): a curve read at an abscissa (inside it, or with
// its end values outside), the first bracketing segment where the strain steps back, and
// the spread of values over runs.
#include "engine/diagnose/curve_statistics.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace triax::diagnose;

TEST_CASE("a curve is read linearly between its readings and not outside them", "[diagnose][curves]") {
    const std::vector<double> x{0.0, 1.0, 3.0}, y{0.0, 10.0, 30.0};
    CHECK(*value_at(x, y, 0.0) == 0.0);
    CHECK(*value_at(x, y, 0.5) == Approx(5.0));
    CHECK(*value_at(x, y, 2.0) == Approx(20.0));
    CHECK(*value_at(x, y, 3.0) == 30.0);
    CHECK_FALSE(value_at(x, y, -0.1));
    CHECK_FALSE(value_at(x, y, 3.1));
    CHECK_FALSE(value_at({}, {}, 0.0));
    CHECK(value_at_clamped(x, y, -5.0) == 0.0);
    CHECK(value_at_clamped(x, y, 9.0) == 30.0);
    CHECK(value_at_clamped(x, y, 2.0) == Approx(20.0));
}

TEST_CASE("where the strain steps back the first bracketing segment is read - a zero-length segment gives its end", "[diagnose][curves]") {
    // 0 -> 2 -> 1.5 -> 3: x = 1.8 lies on the first segment (0, 2) and on (1.5, 3).
    const std::vector<double> x{0.0, 2.0, 1.5, 3.0}, y{0.0, 20.0, 0.0, 30.0};
    CHECK(*value_at(x, y, 1.8) == Approx(18.0));
    const std::vector<double> xs{0.0, 1.0, 1.0, 2.0}, ys{0.0, 1.0, 5.0, 6.0};
    CHECK(*value_at(xs, ys, 1.0) == 1.0);  // the first segment reaches 1.0 at its end
    CHECK(*value_at(xs, ys, 1.5) == Approx(5.5));
}

TEST_CASE("the spread of values over runs: mean, sample variance, extremes", "[diagnose][curves]") {
    const auto s = spread_of({1.0, 2.0, 3.0, 6.0});
    CHECK(s.n == 4);
    CHECK(s.mean == Approx(3.0));
    CHECK(s.variance == Approx((4.0 + 1.0 + 0.0 + 9.0) / 3.0));
    CHECK(s.std() == Approx(std::sqrt(14.0 / 3.0)));
    CHECK(s.min == 1.0);
    CHECK(s.max == 6.0);
    const auto one = spread_of({2.5});
    CHECK(one.variance == 0.0);
    CHECK(one.mean == 2.5);
    const auto none = spread_of({});
    CHECK(none.n == 0);
    CHECK(std::isnan(none.mean));
    CHECK(std::isnan(none.std()));
}
