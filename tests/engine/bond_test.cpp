// Contact bond: holds tension and shear up to its strength, breaks exactly there,
// becomes a frictional contact and is counted by failure mode. Damage scales strength.
#include "engine/contact/bond_shear_strength.hpp"
#include "engine/core/world.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>

using namespace triax;

namespace {

struct BondRun {
    double force_at_break;    // N, the bond force the step before it broke
    double predicted;         // N, strength
    long tension, shear;
};

// Sphere a is held, b is driven at constant velocity (prescribed): the bond force
// grows linearly (k v t) until it reaches the strength.
BondRun pull(const Vec3& direction, double damage) {
    World w;
    const double r = 0.005, kn = 1e6, ks = 5e5, sn = 20.0, ss = 12.0;
    w.set_default_contact_law(test::linear_law(kn, ks, 0.5));
    const int a = w.add_sphere(Vec3(0, 0, 0), r, 2650.0);
    const int b = w.add_sphere(Vec3(2 * r + 1e-6, 0, 0), r, 2650.0);  // 1 um gap, inside tolerance
    REQUIRE(w.bond_contacts(0, 0, 1e-5, sn, ss) == 1);
    w.contacts().damage[0] = damage;
    w.particles().flags[a] |= kFixedVelocity;
    w.particles().flags[b] |= kFixedVelocity;
    w.particles().velocity[b] = 1e-3 * direction;
    w.set_time_step(1e-6);
    double last = 0.0;
    for (int s = 0; s < 200000 && w.intact_bond_count() == 1; ++s) {
        last = direction.x() != 0 ? -w.contacts().normal_force[0] : w.contacts().shear_force[0].norm();
        w.cycle(1);
    }
    const bool tensile = direction.x() != 0;
    return {last, (tensile ? sn : ss) * (1 - damage), w.broken_bonds_tension(), w.broken_bonds_shear()};
}

// Spheres of r = 5 mm bonded 1 um apart with the bond's shear strength ss, then pressed
// 20 um closer (Fn = 20 N); both move only as prescribed. Sphere 1 is the driven one.
World pressed_bonded_pair(const ContactLaw& law, double ss, double damage) {
    World w;
    const double r = 0.005;
    w.set_default_contact_law(law);
    const int a = w.add_sphere(Vec3(0, 0, 0), r, 2650.0);
    const int b = w.add_sphere(Vec3(2 * r + 1e-6, 0, 0), r, 2650.0);
    REQUIRE(w.bond_contacts(0, 0, 1e-5, 100.0, ss) == 1);
    w.contacts().damage[0] = damage;
    w.particles().position[b].x() -= 20e-6;
    w.particles().flags[a] |= kFixedVelocity;
    w.particles().flags[b] |= kFixedVelocity;
    w.set_time_step(1e-6);
    return w;
}

struct ShearBreak {
    double shear;   // N, the bond's shear force the step before it broke
    double normal;  // N, the normal force then
};

// Slides sphere 1 at 1 mm/s across the contact until the bond breaks.
ShearBreak shear_until_break(World& w) {
    w.particles().velocity[1] = Vec3(0, 1e-3, 0);
    ShearBreak out{0.0, 0.0};
    for (int s = 0; s < 200000 && w.intact_bond_count() == 1; ++s) {
        out = {w.contacts().shear_force[0].norm(), w.contacts().normal_force[0]};
        w.cycle(1);
    }
    return out;
}

}  // namespace

TEST_CASE("contact bond breaks in tension at its normal strength, not before", "[engine][bond]") {
    const BondRun run = pull(Vec3::UnitX(), 0.0);
    CHECK(run.force_at_break == Approx(run.predicted).epsilon(0.01));
    CHECK(run.force_at_break < run.predicted);
    CHECK(run.tension == 1);
    CHECK(run.shear == 0);
}

TEST_CASE("contact bond breaks in shear at its shear strength, not before", "[engine][bond]") {
    const BondRun run = pull(Vec3::UnitY(), 0.0);
    CHECK(run.force_at_break == Approx(run.predicted).epsilon(0.01));
    CHECK(run.force_at_break < run.predicted);
    CHECK(run.tension == 0);
    CHECK(run.shear == 1);
}

TEST_CASE("damage scales the bond strength", "[engine][bond]") {
    const BondRun run = pull(Vec3::UnitX(), 0.5);
    CHECK(run.force_at_break == Approx(run.predicted).epsilon(0.01));
    CHECK(run.tension == 1);
}

TEST_CASE("a bonded pair starts unloaded and carries tension, unbonded it does not", "[engine][bond]") {
    World w;
    const double r = 0.005;
    w.set_default_contact_law(test::linear_law(1e6, 5e5, 0.5));
    w.add_sphere(Vec3(0, 0, 0), r, 2650.0);
    w.add_sphere(Vec3(2 * r + 2e-6, 0, 0), r, 2650.0);
    w.bond_contacts(0, 0, 1e-5, 1e3, 1e3);
    w.set_time_step(1e-6);
    w.set_local_damping(0.0);
    w.cycle(1);
    CHECK(std::abs(w.contacts().normal_force[0]) < 1e-12);
    // Pull b away: bonded tension; the gap-free unbonded pair would feel nothing.
    w.particles().external_force[1] = Vec3(1.0, 0, 0);
    w.cycle(2000);
    CHECK(w.contacts().normal_force[0] < 0.0);
    CHECK(w.intact_bond_count() == 1);
}

// Mohr-Coulomb bond (ContactLaw::bond_friction, docs/creep.md "Bond cohesion and its
// corrosion"): in compression the intact bond holds shear up to ss (1 - D) + mu_b Fn,
// so its cohesion adds to friction; PFC's contact bond (mu_b = 0) breaks at ss.
TEST_CASE("a Mohr-Coulomb bond breaks in shear at ss (1 - D) + mu_b Fn, then slides at mu Fn", "[engine][bond]") {
    for (double damage : {0.0, 0.5}) {
        const double ss = 12.0, mu_b = 0.3, mu = 0.5;
        ContactLaw law = test::linear_law(1e6, 5e5, mu);
        law.bond_friction = mu_b;
        World w = pressed_bonded_pair(law, ss, damage);
        const auto [last, fn] = shear_until_break(w);
        INFO("damage " << damage);
        REQUIRE(fn == Approx(20.0).epsilon(0.01));  // the shear motion opens the pair a little
        const double predicted = ss * (1 - damage) + mu_b * fn;  // 18 N intact, 12 N half corroded
        CHECK(last == Approx(predicted).epsilon(0.01));
        CHECK(last < predicted);
        CHECK(last > mu * fn);  // held beyond friction: the bond's cohesion
        CHECK(w.broken_bonds_shear() == 1);
        w.cycle(10);
        CHECK(w.contacts().shear_force[0].norm() == Approx(mu * w.contacts().normal_force[0]).epsilon(1e-6));
    }
}

// Cement interlock (engine/contact/bond_shear_strength.hpp): a bond friction mu_b above
// the grains' mu is carried by the cement, so the excess fades with the damage:
// S = (ss + (mu_b - mu) Fn)(1 - D) + mu Fn. Intact it holds ss + mu_b Fn; fully corroded
// it holds mu Fn, like an unbonded contact.
TEST_CASE("a bond friction above the grains' fades with the bond's damage", "[engine][bond]") {
    const double ss = 12.0, mu_b = 0.8, mu = 0.5, fn = 20.0;
    CHECK(bond_shear_strength(ss, mu_b, mu, fn, 0.0) == Approx(ss + mu_b * fn));
    CHECK(bond_shear_strength(ss, mu_b, mu, fn, 0.5) == Approx(0.5 * (ss + 0.3 * fn) + mu * fn));
    CHECK(bond_shear_strength(ss, mu_b, mu, fn, 1.0) == Approx(mu * fn));
    // mu_b <= mu: the cohesion alone corrodes (the Mohr-Coulomb bond of the presets).
    CHECK(bond_shear_strength(ss, 0.3, mu, fn, 0.5) == Approx(0.5 * ss + 0.3 * fn));
    CHECK(bond_shear_strength(ss, 0.0, mu, fn, 0.25) == Approx(0.75 * ss));
    // Tension carries no friction.
    CHECK(bond_shear_strength(ss, mu_b, mu, -5.0, 0.5) == Approx(0.5 * ss));

    // In the contact law: the half-corroded bond breaks at the faded strength.
    ContactLaw law = test::linear_law(1e6, 5e5, mu);
    law.bond_friction = mu_b;
    World w = pressed_bonded_pair(law, ss, 0.5);
    const auto [last, fn_last] = shear_until_break(w);
    const double predicted = 0.5 * (ss + (mu_b - mu) * fn_last) + mu * fn_last;  // 19 N
    CHECK(last == Approx(predicted).epsilon(0.01));
    CHECK(last < ss * 0.5 + mu_b * fn_last);  // below the un-faded 22 N
    CHECK(w.broken_bonds_shear() == 1);
}

// Cement neck (ContactLaw::bond_rolling_friction): an intact bond resists relative rolling
// elastically (M = kr theta, kr = f ks Rbar^2) up to (mu_r + mu_rb (1 - D)) Rbar Fn; there
// the neck cracks: the bond keeps its cohesion, the contact holds no moment (mu_r = 0) and
// the moment spring's energy is released as bond-break energy.
TEST_CASE("a bond's cement neck holds a rolling moment up to mu_rb (1 - D) Rbar Fn, then cracks", "[engine][bond]") {
    for (double damage : {0.0, 0.5}) {
        const double r = 0.005, ks = 5e5, mu_rb = 0.3;
        ContactLaw law = test::linear_law(1e6, ks, 0.5);
        law.bond_friction = 0.5;
        law.bond_rolling_friction = mu_rb;
        World w = pressed_bonded_pair(law, 1e3, damage);
        // Equal and opposite spins about y: relative rolling, no sliding at the contact point.
        w.particles().angular_velocity[0] = Vec3(0, -0.05, 0);
        w.particles().angular_velocity[1] = Vec3(0, 0.05, 0);
        const double r_bar = 0.5 * r, kr = ks * r_bar * r_bar;
        double last = 0.0, fn = 0.0;
        int steps = 0;
        for (; steps < 400000 && !w.contacts().neck_cracked[0]; ++steps) {
            last = w.contacts().rolling_moment[0].norm();
            fn = w.contacts().normal_force[0];
            w.cycle(1);
        }
        INFO("damage " << damage);
        REQUIRE(w.contacts().neck_cracked[0] == 1);
        const double predicted = mu_rb * (1.0 - damage) * r_bar * fn;
        CHECK(fn == Approx(20.0).epsilon(0.01));
        CHECK(last == Approx(predicted).epsilon(0.01));
        CHECK(last < predicted);
        CHECK(last == Approx(kr * 0.1 * 1e-6 * (steps - 1)).epsilon(0.01));  // elastic up to the crack
        CHECK(w.contacts().rolling_moment[0].norm() == 0.0);
        CHECK(w.intact_bond_count() == 1);  // the cohesion holds
        CHECK(w.energy().bond_break == Approx(0.5 * last * last / kr).epsilon(0.02));
        w.cycle(100);
        CHECK(w.contacts().rolling_moment[0].norm() == 0.0);  // a cracked neck holds no moment
    }
}
