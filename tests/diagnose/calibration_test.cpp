// Calibration: recovers known parameters of a nonlinear residual within a small budget,
// is reproducible for a seed, survives failed runs, and reports sensible uncertainty.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "engine/diagnose/calibration.hpp"

using namespace triax::diagnose;

namespace {
// Residual of y = a (1 - exp(-x / b)) against data made with a = 2, b = 0.3 plus noise.
struct Problem {
    std::vector<ParameterSpec> specs{{"a", "-", 0.5, 5.0, 1.0, false}, {"b", "-", 0.01, 3.0, 1.0, true}};
    std::vector<double> x, y;
    int calls = 0;
    explicit Problem(double noise) {
        std::mt19937_64 rng(11);
        std::normal_distribution<double> nd;
        for (int i = 0; i < 100; ++i) {
            x.push_back(0.02 * i);
            y.push_back(2.0 * (1 - std::exp(-x.back() / 0.3)) + noise * nd(rng));
        }
    }
    BatchEvaluator evaluator(bool fail_some = false) {
        return [this, fail_some](const std::vector<UnitPoint>& batch) {
            std::vector<std::vector<double>> out;
            for (const auto& u : batch) {
                ++calls;
                const double a = to_parameter(specs[0], u[0]), b = to_parameter(specs[1], u[1]);
                std::vector<double> r;
                if (!(fail_some && u[0] > 0.9))
                    for (std::size_t i = 0; i < x.size(); ++i) r.push_back(a * (1 - std::exp(-x[i] / b)) - y[i]);
                out.push_back(r);
            }
            return out;
        };
    }
    UnitPoint start() const {
        return {to_unit(specs[0], specs[0].nominal), to_unit(specs[1], specs[1].nominal)};
    }
};
}  // namespace

TEST_CASE("unit-cube map is inverse of itself, log scale in log space", "[diagnose][calibration]") {
    ParameterSpec lin{"x", "-", 2.0, 6.0, 3.0, false}, lg{"k", "N/m", 1e6, 1e9, 1e7, true};
    CHECK(to_parameter(lin, 0.25) == Approx(3.0));
    CHECK(to_parameter(lg, 0.5) == Approx(std::sqrt(1e6 * 1e9)));
    CHECK(to_unit(lg, to_parameter(lg, 0.3)) == Approx(0.3));
    CHECK(parameter_derivative(lin, 0.7) == Approx(4.0));
}

TEST_CASE("Latin hypercube: one point per stratum on every axis, seeded", "[diagnose][calibration]") {
    const auto d = latin_hypercube(10, 3, 42);
    for (int j = 0; j < 3; ++j) {
        std::vector<int> hits(10, 0);
        for (const auto& p : d) ++hits[static_cast<std::size_t>(p[j] * 10)];
        for (int h : hits) CHECK(h == 1);
    }
    CHECK(latin_hypercube(10, 3, 42)[4] == d[4]);
    CHECK(latin_hypercube(10, 3, 43)[4] != d[4]);
}

TEST_CASE("calibration recovers parameters within the run budget", "[diagnose][calibration]") {
    Problem p(0.01);
    CalibrationSettings st;
    st.start = p.start();
    st.design_runs = 8;
    st.refine_runs = 24;
    const auto r = calibrate(p.evaluator(), st);
    CHECK(r.runs == p.calls);
    CHECK(r.runs <= 1 + 8 + 24);
    CHECK(to_parameter(p.specs[0], r.best[0]) == Approx(2.0).epsilon(0.02));
    CHECK(to_parameter(p.specs[1], r.best[1]) == Approx(0.3).epsilon(0.05));
    const auto sd = parameter_std(p.specs, r, 100.0);
    CHECK(sd[0] > 0.0);
    CHECK(sd[0] < 0.05);  // noise 0.01 on 100 readings: a is known to about 1e-2
    // The true value lies within 4 sigma.
    CHECK(std::abs(to_parameter(p.specs[0], r.best[0]) - 2.0) < 4 * sd[0] + 1e-3);

    Problem q(0.01);
    const auto r2 = calibrate(q.evaluator(), st);
    CHECK(r2.best == r.best);  // reproducible for a seed
}

TEST_CASE("failed runs are scored as infinitely bad, not fatal", "[diagnose][calibration]") {
    Problem p(0.01);
    CalibrationSettings st;
    st.start = p.start();
    st.design_runs = 10;
    st.refine_runs = 20;
    const auto r = calibrate(p.evaluator(true), st);
    CHECK(std::isfinite(r.rss));
    CHECK(to_parameter(p.specs[0], r.best[0]) == Approx(2.0).epsilon(0.05));
    CHECK(std::count_if(r.point_rss.begin(), r.point_rss.end(), [](double v) { return !std::isfinite(v); }) > 0);
}
