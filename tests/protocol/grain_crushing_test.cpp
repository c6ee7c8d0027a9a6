// The crushable-contact law (engine/contact/grain_crushing.hpp): Weibull size effect of the
// grain strength, the elastic-plastic return map and its energy, and the lost overlap that
// stays after unloading (the contraction crushing gives the skeleton).
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "engine/contact/grain_crushing.hpp"
#include "engine/protocol/test_scheme.hpp"

using namespace triax;

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
    ParticleArrays pa;
    const double r = 0.005, kn = 1.0e6, h = 0.1;
    pa.add(Vec3(0, 0, 0), r, 2600.0, 0);
    pa.add(Vec3(0, 0, 2 * r), r, 2600.0, 0);
    ContactStore c;
    c.resize(1);
    c.reset_history(0);
    c.i[0] = 0;
    c.j[0] = 1;
    c.active[0] = 1;
    const std::vector<double> f_c = {200.0, 30.0};  // grain 1 is the weaker
    // Load in small overlap steps to 100 um: the force (elastic part) would be 100 N.
    double dissipated = 0.0;
    for (int step = 1; step <= 100; ++step) {
        pa.position[1].z() = 2 * r - 1.0e-6 * step;
        dissipated += crush_contacts(c, pa, 2, f_c, kn, h).dissipated_j;
    }
    const double delta_p = c.creep_normal_offset[0];
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
    CHECK(c.creep_normal_offset[0] == delta_p);
    // Contacts with a non-grain particle (index >= n_grains) are never crushed.
    pa.position[1].z() = 2 * r - 5.0e-4;
    CHECK(crush_contacts(c, pa, 1, f_c, kn, h).crushing == 0);
}

// ---- static fatigue (delayed crushing) ------------------------------------------------

TEST_CASE("static fatigue: exact update at fixed force, finite life t0 r^-n / (n + 1)", "[crushing][fatigue]") {
    GrainFatigueParams p;
    p.time_s = 3600.0;
    p.exponent = 20.0;
    const double r = 0.9;
    const double life = p.time_s * std::pow(r, -p.exponent) / (p.exponent + 1.0);
    // Early rate: dD/dt = (1/t0) r^n at D = 0.
    const double dt_small = 1e-4 * life;
    CHECK(fatigue_damage_update(0.0, r, dt_small, p) / dt_small == Approx(std::pow(r, p.exponent) / p.time_s).epsilon(1e-3));
    // Exact at fixed force: one step and a hundred steps agree.
    double d = 0.0;
    for (int k = 0; k < 100; ++k) d = fatigue_damage_update(d, r, 0.005 * life, p);
    CHECK(d == Approx(fatigue_damage_update(0.0, r, 0.5 * life, p)).epsilon(1e-9));
    // Closed form: 1 - (1 - D)^(n+1) = t / life.
    CHECK(1.0 - std::pow(1.0 - d, p.exponent + 1.0) == Approx(0.5).epsilon(1e-9));
    // Self-accelerating (the crack's K grows as the strength falls): the damage of the
    // second half of the life is far more than that of the first half.
    const double d_half = d;
    const double d_95 = fatigue_damage_update(d_half, r, 0.45 * life, p);
    CHECK(d_95 - d_half > 2.0 * d_half);
    // Failure at the life: capped at D_max (the fragments still carry load).
    CHECK(fatigue_damage_update(0.0, r, 0.999 * life, p) < kFatigueDamageMax);
    CHECK(fatigue_damage_update(0.0, r, 1.001 * life, p) == kFatigueDamageMax);
    // Static-fatigue law: life ~ (F/F_c)^-n, so a grain at 0.8 of its strength lives
    // (9/8)^20 ~ 10.5 times longer than one at 0.9.
    const double life08 = p.time_s * std::pow(0.8, -p.exponent) / (p.exponent + 1.0);
    CHECK(fatigue_damage_update(0.0, 0.8, 0.9 * life08, p) < kFatigueDamageMax);
    CHECK(fatigue_damage_update(0.0, 0.8, 0.9 * life, p) < 0.05);
    CHECK(life08 / life == Approx(std::pow(9.0 / 8.0, 20.0)));
    // Loads above the strength fatigue at the rate of a grain at its strength (r capped).
    CHECK(fatigue_damage_update(0.0, 1.5, 10.0, p) == Approx(fatigue_damage_update(0.0, 1.0, 10.0, p)));
    // With a higher cap (creep.grain_fatigue_ratio_cap), a grain loaded beyond its intact
    // strength (a shared broken neighbour's load on a hardened contact) fatigues at its own
    // ratio, up to the cap: (1.5)^20 ~ 3,300 times the rate at the strength.
    GrainFatigueParams shared = p;
    shared.ratio_cap = 2.0;
    const double dt_tiny = 1e-6;
    CHECK(fatigue_damage_update(0.0, 1.5, dt_tiny, shared) ==
          Approx(std::pow(1.5, p.exponent) * fatigue_damage_update(0.0, 1.0, dt_tiny, shared)).epsilon(1e-3));
    CHECK(fatigue_damage_update(0.0, 3.0, dt_tiny, shared) == Approx(fatigue_damage_update(0.0, 2.0, dt_tiny, shared)));
    CHECK(fatigue_time_to_failure(0.0, 1.5, shared) == Approx(fatigue_time_to_failure(0.0, 1.0, p) * std::pow(1.5, -p.exponent)));
    // Off (t0 = 0): no damage.
    GrainFatigueParams off;
    CHECK(fatigue_damage_update(0.2, 0.99, 1e9, off) == 0.2);
}

TEST_CASE("static fatigue of grains: peak contact force, weaker grain first, then delayed crushing", "[crushing][fatigue]") {
    ParticleArrays pa;
    const double r = 0.005, kn = 1.0e6, h = 0.02;
    pa.add(Vec3(0, 0, 0), r, 2600.0, 0);
    pa.add(Vec3(0, 0, 2 * r - 25.0e-6), r, 2600.0, 0);  // 25 um overlap: 25 N
    pa.add(Vec3(0, 2 * r, 0), r, 2600.0, 1);              // not a grain (membrane)
    ContactStore c;
    c.resize(2);
    for (int k = 0; k < 2; ++k) c.reset_history(k);
    c.i[0] = 0; c.j[0] = 1; c.active[0] = 1; c.normal_force[0] = 25.0;
    c.i[1] = 0; c.j[1] = 2; c.active[1] = 1; c.normal_force[1] = 90.0;  // grain-membrane: ignored
    const std::vector<double> f_c = {100.0, 30.0};
    std::vector<double> damage(2, 0.0), f_now = f_c;
    GrainFatigueParams p;
    p.time_s = 600.0;
    p.exponent = 10.0;
    // Below both strengths: no crushing now.
    CHECK(crush_contacts(c, pa, 2, f_now, kn, h).crushing == 0);
    // The dry run reports and leaves the state alone.
    const FatigueSummary dry = fatigue_grains(c, 2, f_c, damage, f_now, 60.0, p, false);
    CHECK(dry.grains_damaged == 2);
    CHECK(damage[0] == 0.0);
    CHECK(f_now[1] == 30.0);
    // Grain 1 at 25/30 of its strength fatigues, grain 0 at 25/100 (not 90/100: the
    // membrane contact does not count) hardly.
    fatigue_grains(c, 2, f_c, damage, f_now, 60.0, p);
    CHECK(damage[1] == Approx(fatigue_damage_update(0.0, 25.0 / 30.0, 60.0, p)));
    CHECK(damage[0] == Approx(fatigue_damage_update(0.0, 0.25, 60.0, p)));
    CHECK(damage[0] < 1e-4 * damage[1]);  // (0.25 / 0.83)^10 ~ 6e-6
    CHECK(f_now[1] == Approx(30.0 * (1.0 - damage[1])));
    // Held long enough (past grain 1's life), the contact crushes at the unchanged load:
    // delayed breakage, the creep of a crushable skeleton.
    const double life = p.time_s * std::pow(25.0 / 30.0, -p.exponent) / (p.exponent + 1.0);
    fatigue_grains(c, 2, f_c, damage, f_now, life, p);
    CHECK(damage[1] == kFatigueDamageMax);
    const CrushSummary later = crush_contacts(c, pa, 2, f_now, kn, h);
    CHECK(later.crushing == 1);
    CHECK(c.creep_normal_offset[0] > 0.0);
    // Off: nothing moves.
    std::vector<double> d2(2, 0.0), f2 = f_c;
    CHECK(fatigue_grains(c, 2, f_c, d2, f2, 1e9, GrainFatigueParams{}).grains_damaged == 0);
    CHECK(d2[1] == 0.0);
}

TEST_CASE("static fatigue: time to the next failure is the exact update's inverse", "[crushing][fatigue]") {
    GrainFatigueParams p;
    p.time_s = 1.0e6;
    p.exponent = 20.0;
    // A fresh grain at its strength fails after t0 (1 - 0.1^(n+1)) / (n + 1) ~ t0 / 21.
    const double t1 = fatigue_time_to_failure(0.0, 1.0, p);
    CHECK(t1 == Approx(p.time_s / 21.0).epsilon(1e-12));
    // The update reaches D_max just past it and not just before it, from any damage.
    for (double d0 : {0.0, 0.3, 0.85}) {
        for (double r : {1.0, 0.93}) {
            const double t = fatigue_time_to_failure(d0, r, p);
            INFO("D " << d0 << " r " << r);
            CHECK(fatigue_damage_update(d0, r, t * (1.0 + 1e-6), p) == kFatigueDamageMax);
            CHECK(fatigue_damage_update(d0, r, t * (1.0 - 1e-3), p) < kFatigueDamageMax);
        }
    }
    // A partly damaged grain fails sooner; a failed grain at once; an unloaded one never.
    CHECK(fatigue_time_to_failure(0.3, 1.0, p) < t1);
    CHECK(fatigue_time_to_failure(kFatigueDamageMax, 1.0, p) == 0.0);
    CHECK(std::isinf(fatigue_time_to_failure(0.0, 0.0, p)));
    CHECK(std::isinf(fatigue_time_to_failure(0.0, 1.0, GrainFatigueParams{})));
    // The grains' summary reports the shortest such time among the grains not yet failed:
    // the piece of a creep increment ends there (the load of a broken grain is passed on
    // before the others fatigue further).
    ContactStore c;
    c.resize(2);
    for (int k = 0; k < 2; ++k) c.reset_history(k);
    c.i[0] = 0; c.j[0] = 1; c.active[0] = 1; c.normal_force[0] = 95.0;
    c.i[1] = 1; c.j[1] = 2; c.active[1] = 1; c.normal_force[1] = 50.0;
    const std::vector<double> f_c = {100.0, 200.0, 40.0};
    std::vector<double> damage = {0.0, 0.0, kFatigueDamageMax}, f_now = f_c;
    const FatigueSummary s = fatigue_grains(c, 3, f_c, damage, f_now, 1.0, p, false);
    CHECK(s.next_failure_s == Approx(fatigue_time_to_failure(0.0, 0.95, p)));  // grain 0; grain 2 already failed
    CHECK(s.grains_at_strength == 1);  // grain 2: 50 N on a 40 N grain
    CHECK(s.grains_failed == 1);
}

TEST_CASE("static fatigue scheme fields: bad values are named", "[crushing][fatigue]") {
    protocol::TestScheme s;
    s.creep.grain_fatigue_time_s = -1.0;
    CHECK_THROWS_WITH(s.validate(), Catch::Contains("creep.grain_fatigue_time_s"));
    s.creep.grain_fatigue_time_s = 1.0e6;
    s.creep.grain_fatigue_exponent = 0.5;
    CHECK_THROWS_WITH(s.validate(), Catch::Contains("creep.grain_fatigue_exponent"));
    s.creep.grain_fatigue_exponent = 20.0;
    s.creep.grain_fatigue_ratio_cap = 0.9;
    CHECK_THROWS_WITH(s.validate(), Catch::Contains("creep.grain_fatigue_ratio_cap"));
    s.creep.grain_fatigue_ratio_cap = 1.0;
    CHECK_NOTHROW(s.validate());
}
