// compare_curve: alignment by interpolation, dropped readings, and the metric formulas.
#include <catch2/catch.hpp>

#include <cmath>

#include "engine/diagnose/metrics.hpp"

using triax::diagnose::compare_curve;

TEST_CASE("identical curves give zero error and R^2 = 1", "[diagnose][metrics]") {
    const std::vector<double> x{0, 1, 2, 3}, y{0, 2, 4, 6};
    const auto m = compare_curve(x, y, x, y);
    CHECK(m.n == 4);
    CHECK(m.dropped == 0);
    CHECK(m.rmse == Approx(0.0).margin(1e-15));
    CHECK(m.r2 == Approx(1.0));
    CHECK(m.max_error == Approx(0.0).margin(1e-15));
}

TEST_CASE("model is interpolated onto the lab abscissa", "[diagnose][metrics]") {
    // Model y = 2x sampled coarsely; lab readings in between are matched exactly.
    const std::vector<double> xm{0, 1, 2}, ym{0, 2, 4};
    const std::vector<double> xl{0.25, 0.5, 1.5}, yl{0.5, 1.0, 3.0};
    const auto m = compare_curve(xm, ym, xl, yl);
    REQUIRE(m.n == 3);
    CHECK(m.points[2].model == Approx(3.0));
    CHECK(m.rmse == Approx(0.0).margin(1e-12));
}

TEST_CASE("constant offset: RMSE, NRMSE, max error and sign of the residual", "[diagnose][metrics]") {
    const std::vector<double> x{0, 1, 2, 3, 4}, lab{0, 1, 2, 3, 4};
    std::vector<double> model = lab;
    for (auto& v : model) v += 0.5;
    const auto m = compare_curve(x, model, x, lab);
    CHECK(m.rmse == Approx(0.5));
    CHECK(m.nrmse == Approx(0.5 / 4.0));
    CHECK(m.max_error == Approx(0.5));
    CHECK(m.points[0].residual == Approx(0.5));  // residual = model - lab
    // SS_tot = 10, SS_res = 5 * 0.25
    CHECK(m.r2 == Approx(1.0 - 1.25 / 10.0));
}

TEST_CASE("readings outside the model range are dropped, unsorted model is sorted", "[diagnose][metrics]") {
    const std::vector<double> xm{2, 0, 1}, ym{4, 0, 2};
    const std::vector<double> xl{-1, 0.5, 1.0, 5}, yl{0, 1, 2, 0};
    const auto m = compare_curve(xm, ym, xl, yl);
    CHECK(m.n == 2);
    CHECK(m.dropped == 2);
    CHECK(m.rmse == Approx(0.0).margin(1e-12));
}

TEST_CASE("size mismatch is an error naming the cause", "[diagnose][metrics]") {
    CHECK_THROWS_WITH(compare_curve({0, 1}, {0}, {0}, {0}), Catch::Contains("model ordinate"));
    CHECK_THROWS_WITH(compare_curve({0, 1}, {0, 1}, {0, 1}, {0}), Catch::Contains("lab ordinate"));
}

TEST_CASE("non-finite model values are ignored and a flat lab curve has NRMSE 0", "[diagnose][metrics]") {
    const std::vector<double> xm{0, 1, 2}, ym{1, NAN, 1};
    const std::vector<double> xl{0, 1, 2}, yl{1, 1, 1};
    const auto m = compare_curve(xm, ym, xl, yl);
    CHECK(m.n == 3);
    CHECK(m.nrmse == 0.0);
    CHECK(m.r2 == 1.0);
}
