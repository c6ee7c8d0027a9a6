// The crushable-contact law (engine/contact/grain_crushing.hpp): Weibull size effect of the
// grain strength, the elastic-plastic return map and its energy, and the lost overlap that
// stays after unloading (the contraction crushing gives the skeleton).
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "engine/contact/grain_crushing.hpp"
#include "engine/protocol/test_scheme.hpp"

using namespace triax;

namespace {
// Two grains of radius r stacked on z, just touching, with one active contact (slot 0)
// between them; tests press grain 1 down to load it.
struct TwoGrains {
    ParticleArrays pa;
    ContactStore c;
};
TwoGrains two_grains_touching(double r) {
    TwoGrains g;
    g.pa.add(Vec3(0, 0, 0), r, 2600.0, 0);
    g.pa.add(Vec3(0, 0, 2 * r), r, 2600.0, 0);
    g.c.resize(1);
    g.c.reset_history(0);
    g.c.i[0] = 0;
    g.c.j[0] = 1;
    g.c.active[0] = 1;
    return g;
}
}  // namespace

TEST_CASE("Weibull crushing strength: sigma0 at d0 for the 1/e survivor, falls with size", "[crushing]") {
    GrainCrushingParams p;
    p.strength_pa = 2.0e6;
    p.reference_diameter_m = 0.01;
    p.weibull_modulus = 5.0;
    const double u37 = std::exp(-1.0);
    CHECK(grain_crushing_strength(p, 0.01, u37) == Approx(2.0e6));
    // McDowell & Bolton: sigma_c ~ d^(-3/m); larger grains hold more flaws.
    CHECK(grain_crushing_strength(p, 0.02, u37) / grain_crushing_strength(p, 0.01, u37) == Approx(std::pow(2.0, -0.6)));
    // ... but a larger grain still needs a larger force (F ~ d^(2 - 3/m)).
    CHECK(grain_crushing_force(p, 0.02, u37) > grain_crushing_force(p, 0.01, u37));
    // Weaker survivors (higher u = survives less load) crush at lower stress.
    CHECK(grain_crushing_strength(p, 0.01, 0.9) < grain_crushing_strength(p, 0.01, 0.1));
}

TEST_CASE("Weibull crushing strength: share of grains crushed at a stress follows the survival law", "[crushing]") {
    GrainCrushingParams p;
    p.strength_pa = 1.0e6;
    p.reference_diameter_m = 0.01;
    p.weibull_modulus = 4.0;
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int n = 20000;
    const double d = 0.012, sigma = 0.8e6;
    int crushed = 0;
    for (int k = 0; k < n; ++k)
        if (grain_crushing_strength(p, d, std::max(u(rng), 1e-12)) < sigma) ++crushed;
    const double expected = 1.0 - std::exp(-std::pow(d / p.reference_diameter_m, 3.0) * std::pow(sigma / p.strength_pa, 4.0));
    CHECK(static_cast<double>(crushed) / n == Approx(expected).margin(0.01));
}

TEST_CASE("crush return map: elastic below F_c, on the hardening line above, energy = spring energy released",
          "[crushing]") {
    const double kn = 1.0e6, f_c = 50.0, h = 0.2;
    // Below the yield force: nothing happens.
    const CrushStep none = crush_return_map(40.0 / kn, 0.0, f_c, kn, h);
    CHECK(none.plastic_increment == 0.0);
    CHECK(none.dissipated == 0.0);
    // Above: the elastic force after the map lies on F_y = F_c + h kn delta_p.
    const double delta_p0 = 5.0e-6, delta_e = 120.0 / kn;
    const CrushStep s = crush_return_map(delta_e, delta_p0, f_c, kn, h);
    REQUIRE(s.plastic_increment > 0.0);
    const double f_after = kn * (delta_e - s.plastic_increment);
    CHECK(f_after == Approx(f_c + h * kn * (delta_p0 + s.plastic_increment)));
    CHECK(s.dissipated == Approx(0.5 * kn * delta_e * delta_e - 0.5 * f_after * f_after / kn));
    CHECK(s.dissipated > 0.0);
    // Already on the line: a second map does nothing (idempotent).
    CHECK(crush_return_map(delta_e - s.plastic_increment, delta_p0 + s.plastic_increment, f_c, kn, h).plastic_increment ==
          Approx(0.0).margin(1e-18));
}

TEST_CASE("crushing contact: plastic overlap stays after unloading (lost volume), weaker grain decides", "[crushing]") {
    const double r = 0.005, kn = 1.0e6, h = 0.1;
    auto [pa, c] = two_grains_touching(r);
    const std::vector<double> f_c = {200.0, 30.0};  // grain 1 is the weaker
    // Load in small overlap steps to 100 um: the force (elastic part) would be 100 N.
    double dissipated = 0.0;
    for (int step = 1; step <= 100; ++step) {
        pa.position[1].z() = 2 * r - 1.0e-6 * step;
        dissipated += crush_contacts(c, pa, 2, f_c, kn, h).dissipated_j;
    }
    const double delta_p = c.plastic_overlap[0];
    const double f_el = kn * (1.0e-4 - delta_p);
    // The contact force is held near the weaker grain's yield line, far below 100 N.
    CHECK(f_el == Approx(30.0 + h * kn * delta_p).epsilon(1e-9));
    CHECK(f_el < 100.0);
    // Exact for the bilinear law: delta_p = (kn delta - F_c) / ((1 + h) kn).
    CHECK(delta_p == Approx((kn * 1.0e-4 - 30.0) / ((1.0 + h) * kn)).epsilon(1e-9));
    // Energy: input work of the elastic-plastic path = stored spring + dissipated.
    const double delta_y = 30.0 / kn, k_t = kn * h / (1.0 + h);
    const double work = 0.5 * 30.0 * delta_y + 30.0 * (1.0e-4 - delta_y) + 0.5 * k_t * std::pow(1.0e-4 - delta_y, 2);
    CHECK(dissipated + 0.5 * f_el * f_el / kn == Approx(work).epsilon(0.02));
    // Unloading is elastic: at 1e-4 - f_el/kn the force is zero, and delta_p remains.
    pa.position[1].z() = 2 * r - 1.0e-4 + f_el / kn + 1.0e-9;
    CHECK(crush_contacts(c, pa, 2, f_c, kn, h).crushing == 0);
    CHECK(c.plastic_overlap[0] == delta_p);
    // Contacts with a non-grain particle (index >= n_grains) are never crushed.
    pa.position[1].z() = 2 * r - 5.0e-4;
    CHECK(crush_contacts(c, pa, 1, f_c, kn, h).crushing == 0);
}

TEST_CASE("crushing that breaks the bond: a bonded contact that crushes loses its bond, one that does not keeps it",
          "[crushing]") {
    const double r = 0.005, kn = 1.0e6, h = 0.02;
    auto [pa, c] = two_grains_touching(r);
    const std::vector<double> f_c = {200.0, 30.0};
    c.bonded[0] = 1;
    // 20 N: below the weaker grain's 30 N, no crushing, the bond holds.
    pa.position[1].z() = 2 * r - 20.0 / kn;
    auto s = crush_contacts(c, pa, 2, f_c, kn, h, true);
    CHECK(s.crushing == 0);
    CHECK(s.bonds_broken == 0);
    CHECK(c.bonded[0] == 1);
    // 50 N: the contact crushes and its bond goes with the crushed asperities.
    pa.position[1].z() = 2 * r - 50.0 / kn;
    s = crush_contacts(c, pa, 2, f_c, kn, h, true);
    CHECK(s.crushing == 1);
    CHECK(s.bonds_broken == 1);
    CHECK(c.bonded[0] == 0);
    // Crushing on: an unbonded contact counts no broken bond.
    pa.position[1].z() -= 10.0 / kn;
    s = crush_contacts(c, pa, 2, f_c, kn, h, true);
    CHECK(s.crushing == 1);
    CHECK(s.bonds_broken == 0);
    // Without the option (the default) a crushing contact keeps its bond.
    c.reset_history(0);
    c.active[0] = 1;
    c.bonded[0] = 1;
    pa.position[1].z() = 2 * r - 50.0 / kn;
    s = crush_contacts(c, pa, 2, f_c, kn, h);
    CHECK(s.crushing == 1);
    CHECK(c.bonded[0] == 1);
}
