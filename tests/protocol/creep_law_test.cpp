// The time-dependent contact mechanism on a single contact held in place: delayed slip
// relaxes the shear spring and converges; the update does not depend on how a period is
// split; an aged contact does not creep until its mobilisation rises; asperity wear
// follows the slip and lowers the Coulomb limit; sliding in a hold wears towards the
// slow-slip friction; bond corrosion has a threshold;
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

static creep::RateProcessParams base() {
    creep::RateProcessParams p;
    p.slip_rate_a_m_s = 3e-9;
    p.slip_capacity_m = 1e-5;
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
        p.slip_capacity_m = 1e-9;
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

TEST_CASE("sliding in a creep hold wears the contact towards its slow-slip friction", "[protocol][creep]") {
    auto p = base();
    p.slip_rate_a_m_s = 0.0;  // no delayed slip: only the Coulomb sliding wears
    p.slow_slip_wear_max = 0.2;
    p.slow_slip_wear_length_m = 5e-6;
    World w = two_spheres();
    auto& c = w.contacts();
    creep::RateProcessCreep law(p);
    // Drag j 10 um along the contact plane: 0.8 um of elastic shear, the rest slides.
    w.particles().velocity[1] = Vec3(0, -1e-2, 0);
    w.cycle(10000);
    const double slid = c.sliding_slip[0];
    CHECK(slid == Approx(10e-6 - 0.4 * c.normal_force[0] / 5e5).epsilon(0.05));
    // The loading step's sliding does not count.
    law.forget_sliding(w);
    CHECK(c.sliding_slip[0] == 0.0);
    law.advance(w, 60.0);
    CHECK(c.asperity_wear[0] == 0.0);
    // Sliding in the hold does: wear D_s (1 - exp(-slid / d_c)), and the update reads it once.
    w.cycle(10000);
    const double slid2 = c.sliding_slip[0];
    REQUIRE(slid2 > 5e-6);
    law.advance(w, 60.0);
    const double wear = 0.2 * (1 - std::exp(-slid2 / 5e-6));
    CHECK(c.asperity_wear[0] == Approx(wear));
    CHECK(c.sliding_slip[0] == 0.0);
    law.advance(w, 60.0);
    CHECK(c.asperity_wear[0] == Approx(wear));
    // The slider now holds only mu (1 - D) Fn.
    w.cycle(100);
    CHECK(shear_of(w) == Approx(0.4 * (1 - wear) * c.normal_force[0]).epsilon(1e-6));
    // It never wears beyond D_s, and a contact already worn further keeps its wear.
    w.cycle(30000);  // (j has moved 50 um by now, still in contact)
    REQUIRE(c.active[0]);
    law.advance(w, 60.0);
    CHECK(c.asperity_wear[0] <= 0.2);
    CHECK(c.asperity_wear[0] > 0.199);
    c.asperity_wear[0] = 0.3;
    w.cycle(2000);
    REQUIRE(c.sliding_slip[0] > 0.0);
    law.advance(w, 60.0);
    CHECK(c.asperity_wear[0] == 0.3);
    // Off by default: the same sliding wears nothing.
    World q = two_spheres();
    creep::RateProcessCreep plain(base());
    q.particles().velocity[1] = Vec3(0, -1e-2, 0);
    q.cycle(10000);
    plain.advance(q, 60.0);
    CHECK(q.contacts().asperity_wear[0] == 0.0);
}

TEST_CASE("a bond that broke after corroding leaves a contact of lower friction", "[protocol][creep]") {
    auto p = base();
    p.slip_rate_a_m_s = 0.0;
    p.corroded_bond_friction_loss = 0.5;
    creep::RateProcessCreep law(p);
    // Still bonded though corroded: the cement holds, friction unchanged.
    World w = two_spheres();
    auto& c = w.contacts();
    c.bonded[0] = 1;
    c.damage[0] = 0.4;
    law.advance(w, 60.0);
    CHECK(c.asperity_wear[0] == 0.0);
    // Broken after corroding: friction mu (1 - 0.5), and the slider holds only that.
    c.bonded[0] = 0;
    law.advance(w, 60.0);
    CHECK(c.asperity_wear[0] == 0.5);
    w.particles().velocity[1] = Vec3(0, -1e-2, 0);
    w.cycle(2000);
    CHECK(shear_of(w) == Approx(0.4 * 0.5 * c.normal_force[0]).epsilon(1e-6));
    // A bond that broke uncorroded (at loading, damage 0) leaves clean fracture surfaces.
    World q = two_spheres();
    law.advance(q, 60.0);
    CHECK(q.contacts().asperity_wear[0] == 0.0);
    // Off by default.
    World r = two_spheres();
    r.contacts().damage[0] = 0.4;
    creep::RateProcessCreep plain(base());
    plain.advance(r, 60.0);
    CHECK(r.contacts().asperity_wear[0] == 0.0);
}

TEST_CASE("bond corrosion grows only above its load threshold", "[protocol][creep]") {
    for (double rho : {0.5, 0.95}) {
        World w = two_spheres();
        auto& c = w.contacts();
        c.bonded[0] = 1;
        c.bond_shear_strength[0] = 10.0;
        c.bond_normal_strength[0] = 10.0;
        c.shear_force[0] = Vec3(0, rho * 10.0, 0);
        creep::RateProcessParams p;
        p.bond_corrosion_b1_per_s = 1e-6;
        p.bond_corrosion_threshold = 0.9;
        creep::RateProcessCreep law(p);
        const auto s = law.advance(w, 3600.0);
        if (rho < 0.9) CHECK(s.mean_damage == 0.0);
        else CHECK(s.mean_damage > 0.0);
    }
}

// Secondary flow (docs/creep.md, eq. 1b): fixed spring, Kelvin capacity made negligible
// (s_h = 1e-10 m) so what moves is the flow alone.
static creep::RateProcessParams flow_params() {
    auto p = base();  // A = 3e-9 m/s, beta = 6
    p.slip_capacity_m = 1e-10;
    p.critical_mobilisation = 0.9;
    return p;
}

TEST_CASE("above the critical mobilisation a contact flows steadily past its capacity, down to f_c", "[protocol][creep]") {
    const auto p = flow_params();
    creep::RateProcessCreep law(p);
    World w = two_spheres();
    auto& c = w.contacts();
    const double fn = c.normal_force[0];
    c.shear_force[0] = Vec3(0, 0.95 * 0.4 * fn, 0);
    // Steady: the slip over 10 ms is rate x time, and the same in two halves.
    const double rate = 3e-9 * std::sinh(6.0 * 0.95);
    law.advance(w, 0.005);
    law.advance(w, 0.005);
    const double slip = c.creep_slip[0];
    CHECK(slip == Approx(rate * 0.01).epsilon(0.01));  // f falls by ~1 % of the way to f_c
    CHECK(slip > 4.0 * law.equilibrium_slip(0.95));   // no capacity: far past s_eq(f)
    CHECK(law.flow_slip(0.95, 0.95 * 0.4 * fn, 5e5, 0.01) == Approx(rate * 0.01));
    // Long after, the flow has relaxed the spring to exactly f_c and stopped.
    law.advance(w, 10.0);
    CHECK(shear_of(w) == Approx(0.9 * 0.4 * fn).epsilon(1e-9));
    const double s_end = c.creep_slip[0];
    law.advance(w, 3600.0);
    CHECK(c.creep_slip[0] == Approx(s_end).epsilon(1e-9));
    // Below f_c there is no flow, only the bounded Kelvin slip; f_c > 1 switches it off.
    CHECK(law.flow_slip(0.85, 0.85 * 0.4 * fn, 5e5, 3600.0) == 0.0);
    auto off = p;
    off.critical_mobilisation = 1.5;
    CHECK(creep::RateProcessCreep(off).flow_slip(1.0, 0.4 * fn, 5e5, 3600.0) == 0.0);
}

TEST_CASE("a flowing contact whose wear outpaces its spring keeps flowing (slip-weakening instability)", "[protocol][creep]") {
    // Flow stops at f_c mu (1 - D) Fn, but the slip wears the contact and lowers that
    // limit, so it flows again: the wear per unit slip, mu Fn D_max / s_w, against the
    // spring's ks. Weak wear (s_w = 1 mm): the contact stops near f_c. Strong wear
    // (s_w = 10 nm, mu Fn D_max / s_w = 2e7 N/m > ks = 5e5 N/m): it flows until the
    // asperities are worn out (D -> D_max) and holds only f_c mu (1 - D_max) Fn.
    auto run = [](double s_w) {
        auto p = flow_params();
        p.wear_length_m = s_w;
        p.wear_max = 0.5;
        creep::RateProcessCreep law(p);
        World w = two_spheres();
        w.contacts().shear_force[0] = Vec3(0, 0.95 * 0.4 * w.contacts().normal_force[0], 0);
        for (int k = 0; k < 200; ++k) law.advance(w, 1.0);
        return w;
    };
    const World weak = run(1e-3), strong = run(1e-8);
    const double fn = weak.contacts().normal_force[0];
    CHECK(weak.contacts().asperity_wear[0] < 0.01);
    CHECK(shear_of(weak) > 0.88 * 0.4 * fn);
    CHECK(strong.contacts().asperity_wear[0] > 0.49);
    CHECK(shear_of(strong) == Approx(0.9 * 0.4 * 0.5 * fn).epsilon(0.03));
    CHECK(strong.contacts().creep_slip[0] > 5.0 * weak.contacts().creep_slip[0]);
}

TEST_CASE("an aged contact flows only above its aged threshold, and flowing erases the aging", "[protocol][creep]") {
    auto p = flow_params();
    p.aging_margin = 0.05;
    creep::RateProcessCreep law(p);
    World w = two_spheres();
    auto& c = w.contacts();
    const double fn = c.normal_force[0];
    c.shear_force[0] = Vec3(0, 0.92 * 0.4 * fn, 0);
    law.age(w);
    CHECK(c.flow_threshold[0] == Approx(0.97));
    law.advance(w, 60.0);
    CHECK(shear_of(w) == Approx(0.92 * 0.4 * fn).epsilon(1e-12));  // above f_c, but aged: holds
    c.shear_force[0] = Vec3(0, 0.98 * 0.4 * fn, 0);                 // the next stage's load
    law.advance(w, 60.0);
    CHECK(shear_of(w) == Approx(0.9 * 0.4 * fn).epsilon(1e-9));     // flowed down to f_c
    CHECK(c.flow_threshold[0] == 0.0);
    c.shear_force[0] = Vec3(0, 0.93 * 0.4 * fn, 0);                 // below the old threshold
    law.advance(w, 60.0);
    CHECK(shear_of(w) == Approx(0.9 * 0.4 * fn).epsilon(1e-9));     // flows on from f_c
}

TEST_CASE("flow slip wears the asperities over the flow wear length", "[protocol][creep]") {
    auto p = flow_params();
    p.wear_max = 0.5;
    p.wear_length_m = 1.0;          // Kelvin slip would wear nothing
    p.flow_wear_length_m = 1e-7;
    creep::RateProcessCreep law(p);
    World w = two_spheres();
    auto& c = w.contacts();
    c.shear_force[0] = Vec3(0, 0.95 * 0.4 * c.normal_force[0], 0);
    law.advance(w, 0.01);
    const double slip = c.creep_slip[0];
    REQUIRE(slip > 0.0);
    CHECK(c.asperity_wear[0] == Approx(0.5 * (1 - std::exp(-slip / 1e-7))));
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
    p.bond_corrosion_b1_per_s = 1e-9;
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
    p.bond_corrosion_b1_per_s = 1e-9;
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
