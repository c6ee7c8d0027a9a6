// The time-dependent contact mechanism on a single contact held in place (docs/creep.md,
// section 1): rate-and-state slip against the closed form, logarithmic in time for m = 1 and
// a power of time for m < 1, steeply faster with mobilisation, renewed by a load step,
// unloading its spring (energy booked as creep) and independent of how a period is split;
// bond corrosion has a threshold, accelerates to rupture, and holds the contact.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "engine/core/world.hpp"
#include "engine/creep/rate_state_creep.hpp"

using namespace triax;

namespace {
// Two touching spheres with prescribed (zero) velocity: the contact keeps its geometry.
World two_spheres() {
    World w;
    ContactLaw law;
    law.kn = 1e6;
    law.ks = 5e5;
    law.friction = 0.4;
    w.set_default_contact_law(law);
    w.add_sphere(Vec3(0, 0, 0), 1e-3, 2600.0);
    w.add_sphere(Vec3(1.999e-3, 0, 0), 1e-3, 2600.0);  // 1 um overlap: Fn = 1 N
    for (int k = 0; k < 2; ++k) w.particles().flags[k] |= kFixedVelocity;
    w.set_time_step(1e-7);
    w.cycle(1);
    return w;
}

// The contact at mobilisation f, its state renewed (as after a later stage's loading).
World loaded_pair(const creep::RateStateCreep& law, double f) {
    World w = two_spheres();
    law.begin_stage(w, false);
    w.contacts().shear_force[0] = Vec3(0, f * 0.4 * w.contacts().normal_force[0], 0);
    return w;
}
}  // namespace

// a = 0.01, m = 1, t_r = 60 s; D_c = 1e-12 m keeps the slip far below a Fn / ks = 2e-8 m, so
// the spring barely unloads and the slip is the rate-and-state slip at fixed load. No
// corrosion: each test switches on what it checks.
static creep::RateStateParams base() {
    creep::RateStateParams p;
    p.direct_effect_a = 0.01;
    p.critical_slip_m = 1e-12;
    p.renewed_age_s = 60.0;
    p.state_exponent_m = 1.0;
    p.bond_corrosion_rate_b1_per_s = 0.0;
    return p;
}

static double shear_of(const World& w) { return w.contacts().shear_force[0].norm(); }

// Slip of the contact so far: the shear force it lost over ks.
static double slip_of(const World& w, double fs0) { return (fs0 - shear_of(w)) / 5e5; }

TEST_CASE("rate-and-state slip at a held load is logarithmic in time (m = 1)", "[protocol][creep]") {
    const creep::RateStateCreep law(base());
    World w = loaded_pair(law, 0.9);
    const double fs0 = shear_of(w);
    // Closed form at fixed f: v = (D_c / theta) x, theta = t_r + (1 - x) t, so
    // s(t) = D_c x ln(1 + (1 - x) t / t_r) / (1 - x), x = exp(-mu (1 - f) / a).
    const double x = std::exp(-0.4 * 0.1 / 0.01);
    std::vector<double> per_decade;
    double t = 0.0, s_prev = 0.0;
    for (double t_end : {600.0, 6000.0, 60000.0, 600000.0}) {
        law.advance(w, t_end - t);
        t = t_end;
        const double s = slip_of(w, fs0);
        CHECK(s == Approx(1e-12 * x * std::log1p((1 - x) * t / 60.0) / (1 - x)).epsilon(0.01));
        per_decade.push_back(s - s_prev);
        s_prev = s;
    }
    // Equal slip per decade once t >> t_r: 3 decades, within 5 %.
    CHECK(per_decade[2] == Approx(per_decade[1]).epsilon(0.05));
    CHECK(per_decade[3] == Approx(per_decade[1]).epsilon(0.05));
    // The energy booked is the spring energy released.
    const double f1 = shear_of(w);
    CHECK(w.energy().creep == Approx((fs0 * fs0 - f1 * f1) / (2 * 5e5)).epsilon(1e-6));
}

TEST_CASE("with m < 1 the creep rate falls as t^-m: slip per decade grows by 10^(1-m)", "[protocol][creep]") {
    auto p = base();
    p.state_exponent_m = 0.8;
    const creep::RateStateCreep law(p);
    World w = loaded_pair(law, 0.7);  // x = 3e-6: the state ages at dtheta/dt = 1
    const double fs0 = shear_of(w);
    std::vector<double> at;
    double t = 0.0;
    for (double t_end : {6000.0, 60000.0, 600000.0}) {
        law.advance(w, t_end - t);
        t = t_end;
        at.push_back(slip_of(w, fs0));
    }
    CHECK((at[2] - at[1]) / (at[1] - at[0]) == Approx(std::pow(10.0, 0.2)).epsilon(0.03));
}

TEST_CASE("creep slip rises steeply with the contact's mobilisation", "[protocol][creep]") {
    const creep::RateStateCreep law(base());
    auto slip_at = [&](double f) {
        World w = loaded_pair(law, f);
        const double fs0 = shear_of(w);
        law.advance(w, 3600.0);
        return slip_of(w, fs0);
    };
    const double low = slip_at(0.7), high = slip_at(0.9);
    REQUIRE(low > 0.0);
    // exp(mu (0.9 - 0.7) / a) = exp(8): both states age at dtheta/dt ~ 1.
    CHECK(high / low == Approx(std::exp(8.0)).epsilon(0.03));
}

TEST_CASE("a load step renews the contact's state: creep restarts from the load", "[protocol][creep]") {
    auto p = base();
    p.critical_slip_m = 1e-9;  // the load step below moves the contact 0.16 um = 160 D_c
    const creep::RateStateCreep law(p);
    World w = loaded_pair(law, 0.8);
    law.advance(w, 86400.0);  // a day at S: the state is a day old
    const double fs_day = shear_of(w);
    law.advance(w, 3600.0);
    const double aged_hour = (fs_day - shear_of(w)) / 5e5;
    // A fresh contact at the same load creeps far more in its first hour.
    World fresh = loaded_pair(law, 0.8);
    const double fs0 = shear_of(fresh);
    law.advance(fresh, 3600.0);
    const double fresh_hour = slip_of(fresh, fs0);
    CHECK(fresh_hour > 5.0 * aged_hour);
    // The next stage's load (f 0.8 -> 0.9 at the same Fn) renews the aged contact: its first
    // hour is that of a fresh contact at 0.9.
    law.begin_stage(w, false);
    w.contacts().shear_force[0] = Vec3(0, 0.9 * 0.4 * w.contacts().normal_force[0], 0);
    const double fs_load = shear_of(w);
    law.advance(w, 3600.0);
    World fresh9 = loaded_pair(law, 0.9);
    const double fs9 = shear_of(fresh9);
    law.advance(fresh9, 3600.0);
    CHECK((fs_load - shear_of(w)) / 5e5 == Approx(slip_of(fresh9, fs9)).epsilon(0.01));
}

TEST_CASE("inside a stage a shear change does not renew the state: only the loading step does", "[protocol][creep]") {
    auto p = base();
    p.critical_slip_m = 1e-9;
    const creep::RateStateCreep law(p);
    // Two contacts aged a day at f 0.8; then the same shear change (f 0.8 -> 0.9), once as a
    // stage's loading step (after begin_stage) and once inside the stage (a relaxation).
    World loaded = loaded_pair(law, 0.8), held = loaded_pair(law, 0.8);
    law.advance(loaded, 86400.0);
    law.advance(held, 86400.0);
    law.begin_stage(loaded, false);
    for (World* w : {&loaded, &held}) w->contacts().shear_force[0] = Vec3(0, 0.9 * 0.4 * w->contacts().normal_force[0], 0);
    const double fs_loaded = shear_of(loaded), fs_held = shear_of(held);
    law.advance(loaded, 3600.0);
    law.advance(held, 3600.0);
    CHECK(loaded.contacts().contact_age[0] < 2.0 * 3600.0);   // renewed, then an hour old
    CHECK(held.contacts().contact_age[0] > 86400.0);          // still a day old
    // The held contact creeps at the new load from its old state: far less in the hour.
    CHECK(slip_of(loaded, fs_loaded) > 5.0 * slip_of(held, fs_held));
}

TEST_CASE("the slip unloads the spring, and does not depend on how the period is split", "[protocol][creep]") {
    // D_c large: the slip is limited by the spring, s -> (a Fn / ks) ln(1 + ...).
    auto p = base();
    p.critical_slip_m = 1e-6;
    const creep::RateStateCreep law(p);
    auto slip_after = [&](int pieces) {
        World w = loaded_pair(law, 0.95);
        const double fs0 = shear_of(w);
        for (int k = 0; k < pieces; ++k) law.advance(w, 6000.0 / pieces);
        return slip_of(w, fs0);
    };
    const double one = slip_after(1), many = slip_after(100);
    REQUIRE(one > 0.0);
    CHECK(one == Approx(many).epsilon(0.05));
    // Unloaded by the slip, the contact creeps far less than at its first load: a few
    // a Fn / ks, where the unrelaxed slip would be D_c ln(1 + 100) = 4.6 um.
    CHECK(one < 10.0 * 0.01 * 1.0 / 5e5);
    // And a trial is a dry run.
    World w = loaded_pair(law, 0.95);
    const double fs0 = shear_of(w);
    const auto t = law.trial(w, 60.0);
    CHECK(t.relaxation > 0.0);
    CHECK(shear_of(w) == fs0);
}

// Two touching spheres (Fn = 1 N, r = 1 mm) held in place, bonded with ss = 1 N and
// tn = 10 N under the Mohr-Coulomb bond law (mu = mu_b = 0.4) and the given cement neck,
// carrying the shear force fs_n (N) along y.
static World held_bonded_pair(double fs_n, double bond_rolling_friction = 0.0) {
    World w;
    ContactLaw law;
    law.kn = 1e6;
    law.ks = 5e5;
    law.friction = 0.4;
    law.bond_friction = 0.4;
    law.bond_rolling_friction = bond_rolling_friction;
    w.set_default_contact_law(law);
    w.add_sphere(Vec3(0, 0, 0), 1e-3, 2600.0);
    w.add_sphere(Vec3(1.999e-3, 0, 0), 1e-3, 2600.0);
    for (int k = 0; k < 2; ++k) w.particles().flags[k] |= kFixedVelocity;
    w.set_time_step(1e-7);
    w.cycle(1);
    auto& c = w.contacts();
    c.bonded[0] = 1;
    c.bond_shear_strength[0] = 1.0;
    c.bond_normal_strength[0] = 10.0;
    c.shear_force[0] = Vec3(0, fs_n, 0);
    return w;
}

TEST_CASE("bond corrosion grows only above its load threshold", "[protocol][creep]") {
    for (double rho : {0.5, 0.95}) {
        World w = two_spheres();
        auto& c = w.contacts();
        c.bonded[0] = 1;
        c.bond_shear_strength[0] = 10.0;
        c.bond_normal_strength[0] = 10.0;
        c.shear_force[0] = Vec3(0, rho * 10.0, 0);
        auto p = base();
        p.critical_slip_m = 0.0;
        p.bond_corrosion_rate_b1_per_s = 1e-6;
        p.bond_corrosion_threshold = 0.9;
        creep::RateStateCreep law(p);
        const auto s = law.advance(w, 3600.0);
        if (rho < 0.9) CHECK(s.mean_damage == 0.0);
        else CHECK(s.mean_damage > 0.0);
    }
}

// Stress corrosion of a Mohr-Coulomb bond (docs/creep.md, "Bond cohesion and its
// corrosion"): it is driven by the utilisation of the bond's present strength,
// rho = |Fs| / (ss (1 - D) + mu_b Fn), so a loaded bond corrodes ever faster until rho
// reaches 1 and the DEM breaks it; the integration does not depend on the increments;
// the bond holds its contact (no creep slip while it is intact).
TEST_CASE("a Mohr-Coulomb bond corrodes ever faster until it breaks, whatever the increments", "[protocol][creep]") {
    // Strength 1.0 + 0.4 x 1 = 1.4 N: rho = 0.857.
    auto bonded_pair = [] { return held_bonded_pair(1.2); };
    auto p = base();  // contact creep on: a bonded contact must not use it
    p.bond_corrosion_rate_b1_per_s = 1e-9;
    p.bond_corrosion_b2 = 10.0;
    p.bond_corrosion_threshold = 0.8;
    creep::RateStateCreep law(p);
    World one = bonded_pair(), many = bonded_pair();
    law.advance(one, 3600.0);
    for (int k = 0; k < 100; ++k) law.advance(many, 36.0);
    const double d1 = one.contacts().damage[0];
    CHECK(d1 > 0.0);
    CHECK(d1 == Approx(many.contacts().damage[0]).epsilon(0.02));
    CHECK(one.contacts().shear_force[0].norm() == 1.2);  // no creep slip
    // Accelerating: the second hour corrodes more than the first.
    law.advance(one, 3600.0);
    CHECK(one.contacts().damage[0] - d1 > d1);
    // It breaks once ss (1 - D) + 0.4 <= 1.2, i.e. D >= 0.2, and not before.
    World w = bonded_pair();
    double t = 0.0;
    while (w.contacts().damage[0] < 0.2 && t < 1e6) {
        law.advance(w, 600.0);
        t += 600.0;
        if (w.contacts().damage[0] < 0.19) {
            w.cycle(1);
            REQUIRE(w.intact_bond_count() == 1);
        }
    }
    CHECK(t < 1e6);
    w.cycle(1);
    CHECK(w.intact_bond_count() == 0);
    CHECK(w.broken_bonds_shear() == 1);
    // Below the threshold (rho = 0.71) nothing corrodes.
    World low = bonded_pair();
    low.contacts().shear_force[0] = Vec3(0, 1.0, 0);
    law.advance(low, 86400.0);
    CHECK(low.contacts().damage[0] == 0.0);
}

// The cement neck (ContactLaw::bond_rolling_friction) is part of the bond's cement: its
// moment over its corroded limit (mu_r + mu_rb (1 - D)) Rbar Fn drives the corrosion like
// the shear utilisation does; a cracked neck no longer counts.
TEST_CASE("a bond whose cement neck is loaded near its limit corrodes; a lightly loaded one does not", "[protocol][creep]") {
    const double neck_limit = 0.3 * 0.5e-3 * 1.0;  // mu_rb Rbar Fn, N m
    auto necked_pair = [&](double moment_share) {
        World w = held_bonded_pair(0.2, 0.3);  // shear utilisation 0.2 / 1.4: far below the threshold
        w.contacts().rolling_moment[0] = Vec3(0, 0, moment_share * neck_limit);
        return w;
    };
    auto p = base();
    p.bond_corrosion_rate_b1_per_s = 1e-9;
    p.bond_corrosion_b2 = 10.0;
    p.bond_corrosion_threshold = 0.8;
    creep::RateStateCreep law(p);
    World near = necked_pair(0.85), light = necked_pair(0.5), cracked = necked_pair(0.85);
    cracked.contacts().neck_cracked[0] = 1;
    law.advance(near, 600.0);
    law.advance(light, 600.0);
    law.advance(cracked, 600.0);
    // At first dD/dt = b1 exp(b2 x 0.85) = 4.9e-6 1/s, rising as the neck narrows.
    CHECK(near.contacts().damage[0] > 1e-9 * std::exp(8.5) * 600.0);
    CHECK(near.contacts().damage[0] < 0.1);
    CHECK(light.contacts().damage[0] == 0.0);
    CHECK(cracked.contacts().damage[0] == 0.0);
    CHECK(near.contacts().shear_force[0].norm() == 0.2);  // a necked bond holds its contact: no creep slip
}

TEST_CASE("before the first stage a contact of the consolidated specimen has the consolidation's age", "[protocol][creep]") {
    auto p = base();
    p.consolidated_age_s = 3600.0;
    const creep::RateStateCreep law(p);
    World first = two_spheres();
    law.begin_stage(first, true);
    CHECK(first.contacts().contact_age[0] == 3600.0);
    // Loaded to f 0.8 without moving it by D_c (the first stage's small load), it keeps that
    // age and creeps in its first minute far less than a contact the loading renewed.
    first.contacts().shear_force[0] = Vec3(0, 0.8 * 0.4 * first.contacts().normal_force[0], 0);
    first.contacts().creep_reference_shear[0] = first.contacts().shear_force[0].norm();
    const double fs0 = shear_of(first);
    law.advance(first, 60.0);
    World renewed = loaded_pair(law, 0.8);
    const double fs1 = shear_of(renewed);
    law.advance(renewed, 60.0);
    CHECK(slip_of(renewed, fs1) > 10.0 * slip_of(first, fs0));
    // Before a later stage a contact without a state is young.
    World later = two_spheres();
    law.begin_stage(later, false);
    CHECK(later.contacts().contact_age[0] == p.renewed_age_s);
}
