// Residual layout, phase labels, penalties for readings the model does not reach.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "engine/diagnose/residuals.hpp"

using namespace triax::diagnose;

namespace {
LabCurve shear_curve(double s3) {
    LabCurve c;
    c.kind = CurveKind::Shear;
    c.confining_pa = s3;
    for (int i = 0; i <= 40; ++i) {
        const double e = 0.005 * i;
        c.axial_strain.push_back(e);
        c.deviator_pa.push_back(3e5 * (e / 0.05) * std::exp(1 - e / 0.05));  // peak at 5 %
        c.volumetric_strain.push_back(0.01 * (e / 0.03) * std::exp(1 - e / 0.03) - 0.1 * e);
    }
    return c;
}
LabCurve creep_curve(bool tertiary) {
    LabCurve c;
    c.kind = CurveKind::Creep;
    c.stage = 2;
    c.confining_pa = 100e3;
    for (int i = 0; i <= 60; ++i) {
        const double t = i == 0 ? 0.0 : 30.0 * std::pow(10.0, 4.0 * i / 60.0);  // 30 s .. 3.5 days
        double e = 1e-3 + 2e-4 * std::log1p(t / 60.0) + 1e-9 * t;
        if (tertiary && t > 1e5) e += 1e-13 * (t - 1e5) * (t - 1e5);
        c.time_s.push_back(t);
        c.axial_strain.push_back(e);
    }
    return c;
}
}  // namespace

TEST_CASE("shear curves are split at the peak and at the largest contraction", "[diagnose][residuals]") {
    LabDataset lab{"t", {shear_curve(100e3)}, {}};
    const auto layout = residual_layout(lab);
    REQUIRE(layout.size() == 2);
    CHECK(layout[0].label == "stress_strain@100kPa");
    CHECK(layout[0].unit == "Pa");
    // Peak at 5 % strain = reading 10.
    CHECK(layout[0].phase[10] == "pre_peak");
    CHECK(layout[0].phase[11] == "post_peak");
    CHECK(layout[1].label == "volumetric@100kPa");
    CHECK(layout[1].phase[0] == "contraction");
    CHECK(layout[1].phase.back() == "dilation");
}

TEST_CASE("creep curves are split into the loading (instant) and the creep after it (primary, steady, tertiary)",
          "[diagnose][residuals]") {
    LabDataset lab{"t", {creep_curve(false), creep_curve(true)}, {}};
    lab.curves[1].stage = 3;
    lab.curves[1].axial_strain[0] = 3e-3;  // stage 3 loads further
    const auto layout = residual_layout(lab);
    REQUIRE(layout.size() == 3);
    // The creep of each stage, counted from its first reading.
    CHECK(layout[0].label == "creep-2@100kPa");
    REQUIRE(layout[0].x.size() == 60);
    CHECK(layout[0].x.front() == Approx(30.0 * std::pow(10.0, 4.0 / 60.0)));
    CHECK(layout[0].lab.front() == Approx(2e-4 * std::log1p(layout[0].x.front() / 60.0) + 1e-9 * layout[0].x.front()));
    CHECK(layout[0].phase[0] == "primary");
    // Both stages share one scale: the larger creep range (the tertiary stage's).
    CHECK(layout[0].scale == Approx(layout[1].scale));
    CHECK(layout[1].scale > layout[0].lab.back() - layout[0].lab.front());
    // The loading of each stage: one reading per stage, x = stage; with fewer than 3 stages
    // the scale is at least the largest loading (a range of two is no loading curve).
    CHECK(layout[2].label == "instant@100kPa");
    CHECK(layout[2].x == std::vector<double>{2.0, 3.0});
    CHECK(layout[2].lab == std::vector<double>{1e-3, 3e-3});
    CHECK(layout[2].scale == Approx(3e-3));
    CHECK(layout[2].phase == std::vector<std::string>{"instant", "instant"});
    CHECK(std::count(layout[0].phase.begin(), layout[0].phase.end(), "tertiary") == 0);
    CHECK(std::count(layout[0].phase.begin(), layout[0].phase.end(), "steady") > 0);
    CHECK(layout[1].phase.back() == "tertiary");
}

TEST_CASE("model = lab gives a zero residual, a missing curve gives the full-range penalty", "[diagnose][residuals]") {
    LabDataset lab{"t", {shear_curve(100e3), creep_curve(false)}, {}};
    const auto layout = residual_layout(lab);
    auto r = normalised_residual(layout, lab);
    REQUIRE(r.size() == 41 + 41 + 60 + 1);  // shear q and eps_v, the creep after loading, the loading
    for (double v : r) CHECK(v == Approx(0.0).margin(1e-12));

    LabDataset shear_only{"m", {shear_curve(100e3)}, {}};
    r = normalised_residual(layout, shear_only);
    CHECK(r.back() == 1.0);  // creep curve not produced by the model
    // Model at another confining pressure does not match.
    LabDataset other{"m", {shear_curve(200e3)}, {}};
    r = normalised_residual(layout, other);
    CHECK(r.front() == 1.0);
}

TEST_CASE("a model that loads too far but creeps alike misses only the instant series", "[diagnose][residuals]") {
    LabDataset lab{"t", {creep_curve(false)}, {}};
    const auto layout = residual_layout(lab);
    LabDataset model = lab;
    for (auto& e : model.curves[0].axial_strain) e += 5e-4;  // the whole stage 0.05 % higher
    const auto r = normalised_residual(layout, model);
    REQUIRE(r.size() == 61);
    for (std::size_t i = 0; i < 60; ++i) CHECK(r[i] == Approx(0.0).margin(1e-12));
    CHECK(r[60] == Approx(5e-4 / 1e-3));  // one stage: scaled by its own loading
}

TEST_CASE("phase errors: RMSE in the curve's unit, NRMSE relative to the lab range", "[diagnose][residuals]") {
    LabDataset lab{"t", {shear_curve(100e3)}, {}};
    const auto layout = residual_layout(lab);
    LabDataset model = lab;
    for (auto& q : model.curves[0].deviator_pa) q += 6e3;  // 6 kPa too high everywhere
    const auto errors = phase_errors(layout, normalised_residual(layout, model));
    const auto& all = errors.front();
    CHECK(all.curve == "stress_strain@100kPa");
    CHECK(all.phase == "all");
    CHECK(all.rmse == Approx(6e3));
    CHECK(all.nrmse == Approx(6e3 / layout[0].scale));
    bool pre = false;
    for (const auto& e : errors) pre |= (e.phase == "pre_peak" && e.rmse == Approx(6e3));
    CHECK(pre);
}

TEST_CASE("a dataset with no usable curve is rejected with the reason", "[diagnose][residuals]") {
    LabDataset lab{"empty", {LabCurve{}}, {}};
    CHECK_THROWS_WITH(residual_layout(lab), Catch::Contains("no usable curve"));
}

TEST_CASE("creep given only as deformation is compared on deformation", "[diagnose][residuals]") {
    LabCurve c = creep_curve(false);
    for (double e : c.axial_strain) c.axial_deformation_m.push_back(0.2 * e);
    c.axial_strain.clear();
    LabDataset lab{"t", {c}, {}};
    const auto layout = residual_layout(lab);
    REQUIRE(layout.size() == 2);  // the creep and the loading
    CHECK(layout[0].unit == "m");
    CHECK(layout[1].unit == "m");
    for (double v : normalised_residual(layout, lab)) CHECK(v == Approx(0.0).margin(1e-12));
}
