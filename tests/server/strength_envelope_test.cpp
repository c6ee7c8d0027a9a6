// The strength envelope of shear curves (server/io/strength_envelope_json): Mohr circles
// at the peak and the Mohr-Coulomb fit, checked against numbers worked out by hand.
#include "server/io/strength_envelope_json.hpp"

#include "server/io/diagnosis_json.hpp"

#include <catch2/catch.hpp>

using namespace triax;

namespace {

// A shear curve that peaks at q_peak_kpa at 2 % and softens to 90 % of it at 4 %.
diagnose::LabCurve shear_curve(double sigma3_kpa, double q_peak_kpa) {
    diagnose::LabCurve c;
    c.confining_pa = sigma3_kpa * 1e3;
    c.axial_strain = {0.0, 0.01, 0.02, 0.03, 0.04};
    for (double f : {0.0, 0.7, 1.0, 0.95, 0.9}) c.deviator_pa.push_back(f * q_peak_kpa * 1e3);
    return c;
}

}  // namespace

TEST_CASE("three peaks on c' = 20 kPa, phi' = 35 deg give back c' and phi'", "[server][envelope]") {
    // By hand: N = tan^2(45 + 35/2) = 3.690172, 2 c sqrt(N) = 76.8393 kPa, so
    // sigma1 = N sigma3 + 76.8393 = 261.3479 / 445.8565 / 814.8738 kPa at 50 / 100 / 200 kPa.
    diagnose::LabDataset d;
    d.curves = {shear_curve(50, 211.34790168597993), shear_curve(100, 345.85651829311325),
                shear_curve(200, 614.8737515073798)};
    const auto e = io::strength_envelope_json(d);
    CHECK(e["friction_angle_deg"].get<double>() == Approx(35.0).margin(1e-9));
    CHECK(e["cohesion_kPa"].get<double>() == Approx(20.0).margin(1e-9));
    CHECK(e["n_pressures"] == 3);
    REQUIRE(e["circles"].size() == 3);
    const auto& c = e["circles"][1];
    CHECK(c["sigma3_kPa"].get<double>() == Approx(100.0));
    CHECK(c["sigma1_kPa"].get<double>() == Approx(445.85651829311325));
    CHECK(c["p_kPa"].get<double>() == Approx(100.0 + 345.85651829311325 / 3.0));
    CHECK(c["axial_strain_at_peak_pct"].get<double>() == Approx(2.0));
    // In p'-q: M = 6 sin 35 / (3 - sin 35) = 1.418326, k = 6 c cos 35 / (3 - sin 35) = 40.5116 kPa.
    CHECK(e["p_q_line"]["slope"].get<double>() == Approx(1.4183255840669762).epsilon(1e-9));
    CHECK(e["p_q_line"]["intercept_kPa"].get<double>() == Approx(40.511577115931956).epsilon(1e-9));
}

TEST_CASE("one pressure: the envelope runs through the origin, tangent to its circle", "[server][envelope]") {
    // sigma3 100 kPa, q 300 kPa: N = sigma1 / sigma3 = 4, phi' = 2 (atan 2 - 45 deg) = 36.8699 deg.
    diagnose::LabDataset d;
    d.curves = {shear_curve(100, 300)};
    const auto e = io::strength_envelope_json(d);
    CHECK(e["friction_angle_deg"].get<double>() == Approx(36.86989764584402).epsilon(1e-12));
    CHECK(e["cohesion_kPa"].get<double>() == 0.0);
    CHECK(e["p_q_line"]["intercept_kPa"].get<double>() == 0.0);
}

TEST_CASE("no shear curve with deviator readings: no circle, no fit", "[server][envelope]") {
    diagnose::LabDataset d;
    diagnose::LabCurve creep;
    creep.kind = diagnose::CurveKind::Creep;
    creep.time_s = {0, 60};
    creep.axial_deformation_m = {0, 1e-4};
    d.curves = {creep};
    const auto e = io::strength_envelope_json(d);
    CHECK(e["circles"].empty());
    CHECK(e["friction_angle_deg"].is_null());
    CHECK(e["p_q_line"].is_null());
}

TEST_CASE("a diagnosis report carries the envelope of its base and final model curves", "[server][envelope]") {
    diagnose::DiagnosisReport r;
    r.chosen_effect = "none";
    r.base_curves.curves = {shear_curve(50, 150), shear_curve(100, 260)};
    r.final_curves.curves = {shear_curve(50, 211.34790168597993), shear_curve(100, 345.85651829311325)};
    const auto j = io::diagnosis_report_to_json(r);
    REQUIRE(j.contains("strength_envelope"));
    CHECK(j["strength_envelope"]["base"] == io::strength_envelope_json(r.base_curves));
    CHECK(j["strength_envelope"]["final"]["friction_angle_deg"].get<double>() == Approx(35.0).margin(1e-9));
    CHECK(j["strength_envelope"]["final"]["cohesion_kPa"].get<double>() == Approx(20.0).margin(1e-9));
}
