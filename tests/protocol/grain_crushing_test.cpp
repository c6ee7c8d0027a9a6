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

// Three grains in a chain, 0-1 and 1-2 in contact with the given normal forces (N).
ContactStore grain_chain(double f01, double f12) {
    ContactStore c;
    c.resize(2);
    for (int k = 0; k < 2; ++k) c.reset_history(k);
    c.i[0] = 0; c.j[0] = 1; c.active[0] = 1; c.normal_force[0] = f01;
    c.i[1] = 1; c.j[1] = 2; c.active[1] = 1; c.normal_force[1] = f12;
    return c;
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

TEST_CASE("softening crushing (h < 0): the yield force falls with delta_p to rho F_c, then stays there",
          "[crushing]") {
    const double kn = 1.0e6, f_c = 50.0, h = -0.1, rho = 0.2;
    // On the falling branch the force after the map lies on F_c + h kn delta_p (above rho F_c).
    const double delta_p0 = 10.0e-6, delta_e = 80.0 / kn;
    const CrushStep s = crush_return_map(delta_e, delta_p0, f_c, kn, h, rho);
    REQUIRE(s.plastic_increment > 0.0);
    const double f_after = kn * (delta_e - s.plastic_increment);
    CHECK(f_after == Approx(f_c + h * kn * (delta_p0 + s.plastic_increment)));
    CHECK(f_after < f_c);  // a crushing contact sheds load: softer than the intact grain
    CHECK(f_after > rho * f_c);
    // Far along, the yield force has reached its residual: perfectly plastic at rho F_c.
    const CrushStep far = crush_return_map(80.0 / kn, 500.0e-6, f_c, kn, h, rho);
    CHECK(kn * (80.0 / kn - far.plastic_increment) == Approx(rho * f_c));
    // A step that crosses the residual ends on it, not below it.
    const CrushStep cross = crush_return_map(200.0 / kn, 300.0e-6, f_c, kn, h, rho);
    CHECK(kn * (200.0 / kn - cross.plastic_increment) == Approx(rho * f_c));
    // Idempotent on the line, and with h > 0 the residual changes nothing.
    CHECK(crush_return_map(delta_e - s.plastic_increment, delta_p0 + s.plastic_increment, f_c, kn, h, rho)
              .plastic_increment == Approx(0.0).margin(1e-15));
    CHECK(crush_return_map(120.0 / kn, 5.0e-6, f_c, kn, 0.2, rho).plastic_increment ==
          crush_return_map(120.0 / kn, 5.0e-6, f_c, kn, 0.2).plastic_increment);
}

TEST_CASE("crushing friction loss: a contact that crushes keeps mu (1 - loss), one that does not keeps mu",
          "[crushing]") {
    const double r = 0.005, kn = 1.0e6, h = 0.02, loss = 0.5;
    auto [pa, c] = two_grains_touching(r);
    const std::vector<double> f_c = {200.0, 30.0};
    // 20 N: below the weaker grain's 30 N, no crushing, friction kept.
    pa.position[1].z() = 2 * r - 20.0 / kn;
    CHECK(crush_contacts(c, pa, 2, f_c, kn, h, loss).crushing == 0);
    CHECK(c.asperity_wear[0] == 0.0);
    // 50 N: it crushes and its friction drops to mu (1 - loss).
    pa.position[1].z() = 2 * r - 50.0 / kn;
    CHECK(crush_contacts(c, pa, 2, f_c, kn, h, loss).crushing == 1);
    CHECK(c.asperity_wear[0] == loss);
    // A contact already worn further by creep keeps its larger wear.
    c.asperity_wear[0] = 0.7;
    pa.position[1].z() -= 10.0 / kn;
    CHECK(crush_contacts(c, pa, 2, f_c, kn, h, loss).crushing == 1);
    CHECK(c.asperity_wear[0] == 0.7);
    // Without the option (the default) crushing leaves the friction alone.
    c.reset_history(0);
    c.active[0] = 1;
    pa.position[1].z() = 2 * r - 50.0 / kn;
    CHECK(crush_contacts(c, pa, 2, f_c, kn, h).crushing == 1);
    CHECK(c.asperity_wear[0] == 0.0);
}

TEST_CASE("crushing that breaks the bond: a bonded contact that crushes loses its bond, one that does not keeps it",
          "[crushing]") {
    const double r = 0.005, kn = 1.0e6, h = 0.02;
    auto [pa, c] = two_grains_touching(r);
    const std::vector<double> f_c = {200.0, 30.0};
    c.bonded[0] = 1;
    // 20 N: below the weaker grain's 30 N, no crushing, the bond holds.
    pa.position[1].z() = 2 * r - 20.0 / kn;
    auto s = crush_contacts(c, pa, 2, f_c, kn, h, 0.0, 0.0, true);
    CHECK(s.crushing == 0);
    CHECK(s.bonds_broken == 0);
    CHECK(c.bonded[0] == 1);
    // 50 N: the contact crushes and its bond goes with the crushed asperities.
    pa.position[1].z() = 2 * r - 50.0 / kn;
    s = crush_contacts(c, pa, 2, f_c, kn, h, 0.0, 0.0, true);
    CHECK(s.crushing == 1);
    CHECK(s.bonds_broken == 1);
    CHECK(c.bonded[0] == 0);
    // Crushing on: an unbonded contact counts no broken bond.
    pa.position[1].z() -= 10.0 / kn;
    s = crush_contacts(c, pa, 2, f_c, kn, h, 0.0, 0.0, true);
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
    const ContactStore c = grain_chain(95.0, 50.0);
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

// ---- load-dependent fatigue options (session 7; docs/creep.md "Load-dependent fatigue drive")

namespace {
// A grain 0 of radius r at the origin with ball neighbours at the given unit directions
// (at distance 2r), each pushing on it with the given compressive force: contact k between
// grain 0 (i) and neighbour k + 1 (j), force_on_j = F n (n from 0 to the neighbour).
struct Cluster {
    ParticleArrays pa;
    ContactStore c;
    Cluster(double r, const std::vector<Vec3>& dirs, const std::vector<double>& forces) {
        pa.add(Vec3::Zero(), r, 2600.0, 0);
        for (const auto& d : dirs) pa.add(2.0 * r * d.normalized(), r, 2600.0, 0);
        c.resize(dirs.size());
        for (std::size_t k = 0; k < dirs.size(); ++k) {
            c.reset_history(k);
            c.i[k] = 0;
            c.j[k] = static_cast<int>(k) + 1;
            c.active[k] = 1;
            c.normal_force[k] = forces[k];
            c.force_on_j[k] = forces[k] * dirs[k].normalized();
        }
    }
    double drive(int grain, FatigueDrive d, double f_c = 1.0) const {
        std::vector<double> ratio;
        const std::vector<double> fc(pa.size(), f_c);
        grain_drive_ratios(c, nullptr, &pa, static_cast<int>(pa.size()), fc, d, ratio);
        return ratio[static_cast<std::size_t>(grain)];
    }
};
}  // namespace

TEST_CASE("fatigue drive from the grain's stress: F/d^2 for a diametral pair, none under equal all-round load",
          "[crushing][fatigue]") {
    const double r = 0.005, F = 40.0;
    const Vec3 x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
    // Two opposite forces F: the equivalent diametral force is F (the Weibull strength's
    // F/d^2 convention), the same as the peak contact force.
    const Cluster pair(r, {z, -z}, {F, F});
    CHECK(pair.drive(0, FatigueDrive::GrainStress) == Approx(F));
    CHECK(pair.drive(0, FatigueDrive::PeakForce) == Approx(F));
    // The same forces from six sides: no deviatoric load, no splitting drive, while the
    // peak force (the session-5 law) still says "at F".
    const Cluster iso(r, {x, -x, y, -y, z, -z}, {F, F, F, F, F, F});
    CHECK(iso.drive(0, FatigueDrive::GrainStress) == Approx(0.0).margin(1e-9 * F));
    CHECK(iso.drive(0, FatigueDrive::PeakForce) == Approx(F));
    // Lateral confinement at F/2 halves it: sigma_1 - sigma_3 from F - F/2.
    const Cluster conf(r, {x, -x, y, -y, z, -z}, {F / 2, F / 2, F / 2, F / 2, F, F});
    CHECK(conf.drive(0, FatigueDrive::GrainStress) == Approx(F / 2));
    // Any orientation: a pair along a tilted axis gives the same.
    const Vec3 t = Vec3(1, 2, -0.5).normalized();
    CHECK(Cluster(r, {t, -t}, {F, F}).drive(0, FatigueDrive::GrainStress) == Approx(F));
    // Uncapped: the drive rises with the load (1.5 x the forces, 1.5 x the drive) for a grain
    // already beyond its strength, where the capped law gives the same rate.
    const Cluster more(r, {z, -z}, {1.5 * F, 1.5 * F});
    CHECK(more.drive(0, FatigueDrive::GrainStress, F) == Approx(1.5));
    GrainFatigueParams capped;
    capped.time_s = 1.0e8;
    GrainFatigueParams stress = capped;
    stress.drive = FatigueDrive::GrainStress;
    CHECK(fatigue_time_to_failure(0.0, 1.5, capped) == Approx(fatigue_time_to_failure(0.0, 1.0, capped)));
    CHECK(fatigue_time_to_failure(0.0, 1.0, stress) / fatigue_time_to_failure(0.0, 1.5, stress) ==
          Approx(std::pow(1.5, stress.exponent)));
    // A platen contact counts like a ball: grain on a wall below, a ball above.
    ParticleArrays pa;
    pa.add(Vec3::Zero(), r, 2600.0, 0);
    pa.add(Vec3(0, 0, 2 * r), r, 2600.0, 0);
    ContactStore c;
    c.resize(1);
    c.reset_history(0);
    c.i[0] = 0; c.j[0] = 1; c.active[0] = 1; c.normal_force[0] = F; c.force_on_j[0] = F * z;
    WallContactStore w;
    w.resize(1);
    w.particle[0] = 0; w.wall[0] = 0; w.active[0] = 1;
    w.contact_point[0] = Vec3(0, 0, -r);
    w.force_on_particle[0] = F * z;
    std::vector<double> ratio;
    grain_drive_ratios(c, &w, &pa, 2, {F, F}, FatigueDrive::GrainStress, ratio);
    CHECK(ratio[0] == Approx(1.0));
    CHECK(ratio[1] == Approx(0.5));  // grain 1 touches grain 0 only (no reaction on its top)
}

TEST_CASE("instant crushing: grains whose life is shorter than the instant life fail at once, the others fatigue on",
          "[crushing][fatigue]") {
    GrainFatigueParams p;
    p.time_s = 1.0e8;
    p.exponent = 20.0;
    p.drive = FatigueDrive::PeakForce;
    p.instant_life_s = 1.0;
    const std::vector<double> f_c = {10.0, 10.0, 10.0, 10.0};
    // Lives t0 r^-20 (1 - 0.1^21) / 21: r = 2.5 -> 0.4 s, 2.0 -> 4.5 s, 1.0 -> 55 days; grain 3
    // has failed already.
    const std::vector<double> ratio = {2.5, 2.0, 1.0, 3.0};
    std::vector<double> damage = {0.0, 0.0, 0.0, kFatigueDamageMax}, f_now = {10.0, 10.0, 10.0, 1.0};
    CHECK(fatigue_time_to_failure(0.0, 2.5, p) < 1.0);
    CHECK(fatigue_time_to_failure(0.0, 2.0, p) > 1.0);
    CHECK(fail_short_lived_grains(ratio, nullptr, f_c, damage, f_now, p) == 1);
    CHECK(damage[0] == kFatigueDamageMax);
    CHECK(f_now[0] == Approx(10.0 * (1.0 - kFatigueDamageMax)));
    CHECK(damage[1] == 0.0);
    CHECK(damage[2] == 0.0);
    // At the same forces nothing is left to fail at once; the next failure is grain 1's,
    // a time step for the schedule.
    CHECK(fail_short_lived_grains(ratio, nullptr, f_c, damage, f_now, p) == 0);
    const FatigueSummary s = fatigue_grains(ratio, nullptr, f_c, damage, f_now, 0.5, p, false);
    CHECK(s.next_failure_s == Approx(fatigue_time_to_failure(0.0, 2.0, p)));
    // Off (instant life 0, the default): no grain fails at once, however short its life.
    GrainFatigueParams off = p;
    off.instant_life_s = 0.0;
    std::vector<double> d2(4, 0.0), f2 = f_c;
    CHECK(fail_short_lived_grains(ratio, nullptr, f_c, d2, f2, off) == 0);
}

TEST_CASE("strength spread of lives: brittle lifetime law t_f = B S^(n-2) sigma^-n", "[crushing][fatigue]") {
    GrainFatigueParams p;
    p.time_s = 1.0e7;
    p.exponent = 20.0;
    p.drive = FatigueDrive::PeakForce;
    const double s_ref = 0.6e6;
    // At the same ratio r a grain twice as strong lives a quarter as long ...
    const double weak = fatigue_life_scale(0.6e6, s_ref), strong = fatigue_life_scale(1.2e6, s_ref);
    CHECK(weak == Approx(1.0));
    CHECK(strong == Approx(0.25));
    CHECK(fatigue_time_to_failure(0.0, 0.9, p, strong) == Approx(0.25 * fatigue_time_to_failure(0.0, 0.9, p, weak)));
    // ... but at the same stress sigma it lives 2^(n-2) times longer (ratio sigma / S halves).
    const double sigma = 0.5e6;
    const double t_weak = fatigue_time_to_failure(0.0, sigma / 0.6e6, p, weak);
    const double t_strong = fatigue_time_to_failure(0.0, sigma / 1.2e6, p, strong);
    CHECK(t_strong / t_weak == Approx(std::pow(2.0, p.exponent - 2.0)));
    // The update and the time to failure use the same scaled t0.
    const double t = fatigue_time_to_failure(0.2, 1.1, p, strong);
    CHECK(fatigue_damage_update(0.2, 1.1, t * (1.0 + 1e-6), p, strong) == kFatigueDamageMax);
    CHECK(fatigue_damage_update(0.2, 1.1, t * (1.0 - 1e-3), p, strong) < kFatigueDamageMax);
}

TEST_CASE("capped peak-force drive through the general path is the session-5 law", "[crushing][fatigue]") {
    const ContactStore c = grain_chain(95.0, 130.0);
    const std::vector<double> f_c = {100.0, 200.0, 40.0};
    GrainFatigueParams p;
    p.time_s = 1.0e6;
    std::vector<double> ratio;
    grain_drive_ratios(c, nullptr, nullptr, 3, f_c, FatigueDrive::CappedPeakForce, ratio);
    CHECK(ratio[2] == Approx(130.0 / 40.0));  // reported uncapped; the law caps it
    std::vector<double> d1(3, 0.0), f1 = f_c, d2(3, 0.0), f2 = f_c;
    const FatigueSummary a = fatigue_grains(c, 3, f_c, d1, f1, 3600.0, p);
    const FatigueSummary b = fatigue_grains(ratio, nullptr, f_c, d2, f2, 3600.0, p);
    for (int i = 0; i < 3; ++i) CHECK(d1[i] == d2[i]);
    CHECK(a.next_failure_s == b.next_failure_s);
    CHECK(d1[2] == Approx(fatigue_damage_update(0.0, 1.0, 3600.0, p)));
}

TEST_CASE("fatigue option fields: bad instant life is named", "[crushing][fatigue]") {
    protocol::TestScheme s;
    s.creep.grain_fatigue_instant_life_s = -1.0;
    CHECK_THROWS_WITH(s.validate(), Catch::Contains("creep.grain_fatigue_instant_life_s"));
    s.creep.grain_fatigue_instant_life_s = 1.0;
    CHECK_NOTHROW(s.validate());
}
