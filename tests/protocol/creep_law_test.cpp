// The time-dependent contact mechanism on a single contact held in place: delayed slip
// relaxes the shear spring and converges; the update does not depend on how a period is
// split; an aged contact does not creep until its mobilisation rises; asperity wear
// follows the slip and lowers the Coulomb limit; bond corrosion has a threshold;
// dissipation is booked as creep energy.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "engine/core/world.hpp"
#include "engine/creep/rate_process_creep.hpp"

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
}  // namespace

// A fast law on one contact (rates of nm/s, not the paper's calibration), no aging, no wear,
// no corrosion: each test switches on what it checks.
static creep::RateProcessParams base() {
    creep::RateProcessParams p;
    p.slip_rate_a_m_s = 3e-9;
    p.slip_beta = 6.0;
    p.slip_hardening_length_m = 1e-5;
    p.capacity_offset = 0.05;
    p.aging_margin = 0.0;
    p.wear_length_m = 0.0;
    p.wear_max = 0.0;
    p.bond_corrosion_rate_b1_per_s = 0.0;
    return p;
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

static double shear_of(const World& w) { return w.contacts().shear_force[0].norm(); }

TEST_CASE("delayed slip relaxes the shear force and converges", "[protocol][creep]") {
    World w = two_spheres();
    auto& c = w.contacts();
    REQUIRE(c.active[0]);
    const double fn = c.normal_force[0];
    c.shear_force[0] = Vec3(0, 0.6 * 0.4 * fn, 0);  // f = 0.6
    creep::RateProcessCreep law(base());
    std::vector<double> fs;
    for (int k = 0; k < 40; ++k) {
        law.advance(w, 60.0);
        fs.push_back(shear_of(w));
    }
    for (std::size_t k = 1; k < fs.size(); ++k) CHECK(fs[k] <= fs[k - 1]);
    CHECK(fs.back() < 0.6 * 0.4 * fn);
    // Converging: the last ten minutes relax far less than the first ten.
    CHECK((fs[29] - fs[39]) < 0.2 * (0.6 * 0.4 * fn - fs[9]));
    CHECK(w.energy().creep > 0.0);
    CHECK(c.creep_slip[0] > 0.0);
    // The energy booked is the spring energy released.
    const double f0 = 0.6 * 0.4 * fn;
    CHECK(w.energy().creep == Approx((f0 * f0 - fs.back() * fs.back()) / (2 * 5e5)).epsilon(1e-9));
}

TEST_CASE("at fixed mobilisation the slip does not depend on how the period is split", "[protocol][creep]") {
    // Slip small next to the spring's elastic displacement: f barely changes, so the
    // exact exponential update must give the same slip for one step or a hundred.
    auto slip_after = [](int pieces) {
        World w = two_spheres();
        w.contacts().shear_force[0] = Vec3(0, 0.5 * 0.4 * w.contacts().normal_force[0], 0);
        auto p = base();
        p.slip_hardening_length_m = 1e-9;
        creep::RateProcessCreep law(p);
        for (int k = 0; k < pieces; ++k) law.advance(w, 600.0 / pieces);
        return w.contacts().creep_slip[0];
    };
    const double one = slip_after(1), many = slip_after(100);
    REQUIRE(one > 0.0);
    CHECK(one == Approx(many).epsilon(0.02));
    // And a trial is a dry run.
    World w = two_spheres();
    w.contacts().shear_force[0] = Vec3(0, 0.2, 0);
    creep::RateProcessCreep law(base());
    const auto t = law.trial(w, 60.0);
    CHECK(t.relaxation > 0.0);
    CHECK(shear_of(w) == 0.2);
    CHECK(w.contacts().creep_slip[0] == 0.0);
}

TEST_CASE("an aged contact creeps only when its mobilisation rises", "[protocol][creep]") {
    World w = two_spheres();
    auto& c = w.contacts();
    const double fn = c.normal_force[0];
    c.shear_force[0] = Vec3(0, 0.5 * 0.4 * fn, 0);
    creep::RateProcessCreep law(base());
    law.age(w);
    CHECK(c.creep_slip[0] == Approx(law.equilibrium_slip(0.5)));
    law.advance(w, 3600.0);
    CHECK(shear_of(w) == Approx(0.5 * 0.4 * fn).epsilon(1e-12));  // no creep at the aged load
    c.shear_force[0] = Vec3(0, 0.7 * 0.4 * fn, 0);                 // the next stage's load
    law.advance(w, 3600.0);
    CHECK(shear_of(w) < 0.7 * 0.4 * fn);
}

TEST_CASE("asperity wear follows the creep slip and lowers the Coulomb limit", "[protocol][creep]") {
    auto p = base();
    p.wear_length_m = 2e-6;
    p.wear_max = 0.5;
    World w = two_spheres();
    auto& c = w.contacts();
    c.shear_force[0] = Vec3(0, 0.5 * 0.4 * c.normal_force[0], 0);
    creep::RateProcessCreep law(p);
    const auto s = law.advance(w, 600.0);
    const double slip = c.creep_slip[0];
    REQUIRE(slip > 0.0);
    const double wear = c.asperity_wear[0];
    CHECK(wear == Approx(0.5 * (1 - std::exp(-slip / 2e-6))));
    CHECK(s.mean_asperity_wear == Approx(wear));
    // The engine's slider now holds only mu (1 - wear) Fn: push the contact further along
    // its shear force (the force on j opposes j's motion).
    w.particles().velocity[1] = Vec3(0, -1e-2, 0);
    w.cycle(1000);
    CHECK(shear_of(w) == Approx(0.4 * (1 - wear) * c.normal_force[0]).epsilon(1e-6));
    // No wear without slip.
    World q = two_spheres();
    q.contacts().shear_force[0] = Vec3(0, 0.1, 0);
    auto p0 = p;
    p0.slip_rate_a_m_s = 0.0;
    creep::RateProcessCreep still(p0);
    still.advance(q, 3600.0);
    CHECK(q.contacts().asperity_wear[0] == 0.0);
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
        p.slip_rate_a_m_s = 0.0;
        p.bond_corrosion_rate_b1_per_s = 1e-6;
        p.bond_corrosion_threshold = 0.9;
        creep::RateProcessCreep law(p);
        const auto s = law.advance(w, 3600.0);
        if (rho < 0.9) CHECK(s.mean_damage == 0.0);
        else CHECK(s.mean_damage > 0.0);
    }
}

// Stress corrosion of a Mohr-Coulomb bond (docs/creep.md, "Bond cohesion and its
// corrosion"): it is driven by the utilisation of the bond's present strength,
// rho = |Fs| / (ss (1 - D) + mu_b Fn), so a loaded bond corrodes ever faster until rho
// reaches 1 and the DEM breaks it; the integration does not depend on the increments;
// the bond holds its contact (no delayed slip while it is intact).
TEST_CASE("a Mohr-Coulomb bond corrodes ever faster until it breaks, whatever the increments", "[protocol][creep]") {
    // Strength 1.0 + 0.4 x 1 = 1.4 N: rho = 0.857.
    auto bonded_pair = [] { return held_bonded_pair(1.2); };
    auto p = base();  // delayed slip on: a bonded contact must not use it
    p.bond_corrosion_rate_b1_per_s = 1e-9;
    p.bond_corrosion_b2 = 10.0;
    p.bond_corrosion_threshold = 0.8;
    creep::RateProcessCreep law(p);
    World one = bonded_pair(), many = bonded_pair();
    law.advance(one, 3600.0);
    for (int k = 0; k < 100; ++k) law.advance(many, 36.0);
    const double d1 = one.contacts().damage[0];
    CHECK(d1 > 0.0);
    CHECK(d1 == Approx(many.contacts().damage[0]).epsilon(0.02));
    CHECK(one.contacts().creep_slip[0] == 0.0);
    CHECK(one.contacts().shear_force[0].norm() == 1.2);
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
    creep::RateProcessCreep law(p);
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
    CHECK(near.contacts().creep_slip[0] == 0.0);  // a necked bond holds its contact: no delayed slip
}
