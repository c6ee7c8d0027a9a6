// The protocol's closed-form parts: gradation Eq. 2-3, stress level Eq. 1, the physical-time
// schedule, coordinate translation, the moisture -> bond strength relation.
#include <catch2/catch.hpp>

#include <numeric>

#include "engine/creep/coordinate_translation.hpp"
#include "engine/creep/moisture_bond.hpp"
#include "engine/creep/time_schedule.hpp"
#include "engine/protocol/gradation.hpp"
#include "engine/protocol/stress_level.hpp"

using namespace triax;

TEST_CASE("fines below the cut-off are lumped at their mass-weighted mean radius (Eq. 2)", "[protocol]") {
    protocol::GradationSpec g;
    g.kind = protocol::GradationSpec::Kind::SieveCurve;
    g.fines_cutoff_m = 1e-3;
    // 10 % between 0.25-0.5 mm, 20 % between 0.5-1 mm, 70 % between 1-10 mm (diameters).
    g.sieve_curve = {{0.25e-3, 0.0}, {0.5e-3, 10.0}, {1e-3, 30.0}, {10e-3, 100.0}};
    const auto cls = protocol::size_classes(g);
    REQUIRE(cls.size() == 2);
    const double expected = (0.1 * 0.5 * (0.125e-3 + 0.25e-3) + 0.2 * 0.5 * (0.25e-3 + 0.5e-3)) / 0.3;
    CHECK(cls[0].r_lo_m == Approx(expected));
    CHECK(cls[0].mass_fraction == Approx(0.3));
    CHECK(protocol::weighted_fines_radius_m(g) == Approx(expected));
    std::mt19937_64 rng(3);
    const auto radii = protocol::draw_radii(g, 1e-5, rng);
    double v = 0.0;
    for (double r : radii) v += 4.0 / 3.0 * 3.14159265358979 * r * r * r;
    CHECK(v >= 1e-5);
    CHECK(radii.front() >= radii.back());
}

TEST_CASE("radius-ratio gradation spans Rmin to Rmin x ratio (Eq. 3)", "[protocol]") {
    protocol::GradationSpec g;  // paper: 0.5 mm, 39.712
    CHECK(protocol::gradation_r_max_m(g) == Approx(0.5e-3 * 39.712));
    std::mt19937_64 a(7), b(7);
    CHECK(protocol::draw_radii(g, 1e-4, a) == protocol::draw_radii(g, 1e-4, b));
}

TEST_CASE("Eq. 1 is q over the Mohr-Coulomb failure deviator", "[protocol]") {
    // c = 25 kPa, phi = 32 deg, sigma3 = 100 kPa: q_f = (2c cos + 2 s3 sin)/(1 - sin)
    const double qf = protocol::mohr_coulomb_failure_deviator_pa(100e3, 25e3, 32.0);
    CHECK(qf == Approx((2 * 25e3 * std::cos(0.5585) + 2 * 100e3 * std::sin(0.5585)) / (1 - std::sin(0.5585))).epsilon(1e-3));
    CHECK(protocol::stress_level_eq1(0.4 * qf, 100e3, 25e3, 32.0) == Approx(0.4));
    CHECK(protocol::deviator_for_stress_level_eq1(0.8, 100e3, 25e3, 32.0) == Approx(0.8 * qf));
}

TEST_CASE("creep time increments grow geometrically and end exactly at the duration", "[protocol][creep]") {
    const auto dts = creep::creep_time_increments(86400.0, 1.0, 1.25, 3600.0);
    CHECK(std::accumulate(dts.begin(), dts.end(), 0.0) == Approx(86400.0));
    CHECK(dts.front() == Approx(1.0));
    CHECK(dts[1] == Approx(1.25));
    for (double d : dts) CHECK(d <= 3600.0 + 1e-9);
    CHECK(dts.size() < 80);
}

TEST_CASE("coordinate translation moves each stage's origin to its loading instant", "[protocol][creep]") {
    std::vector<creep::TimeDeformation> raw = {{0, 1.0}, {100, 1.5}, {200, 1.6}, {200, 3.0}, {300, 3.4}};
    const auto st2 = creep::translate_stage(raw, 200, 300, 1.6);
    REQUIRE(st2.size() == 2);
    CHECK(st2[0].time == 0.0);
    CHECK(st2[0].deformation == Approx(1.4));
    CHECK(st2[1].time == Approx(100.0));
    CHECK(st2[1].deformation == Approx(1.8));
}

TEST_CASE("bond strength falls with moisture above optimum, D and E weaker than B", "[protocol][creep]") {
    CHECK(creep::bond_strength_factor(0.089) == Approx(1.0));
    CHECK(creep::bond_strength_factor(0.05) == Approx(1.0));
    const double d = creep::bond_strength_factor(0.102), e = creep::bond_strength_factor(0.121);
    CHECK(d < 1.0);
    CHECK(e < d);
    CHECK(d == Approx(std::exp(-15.0 * 0.013)));
}
