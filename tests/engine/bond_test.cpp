// Contact bond: holds tension and shear up to its strength, breaks exactly there,
// becomes a frictional contact and is counted by failure mode. Damage scales strength.
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
        World w;
        const double r = 0.005, kn = 1e6, ks = 5e5, ss = 12.0, mu_b = 0.3, mu = 0.5;
        ContactLaw law = test::linear_law(kn, ks, mu);
        law.bond_friction = mu_b;
        w.set_default_contact_law(law);
        const int a = w.add_sphere(Vec3(0, 0, 0), r, 2650.0);
        const int b = w.add_sphere(Vec3(2 * r + 1e-6, 0, 0), r, 2650.0);
        REQUIRE(w.bond_contacts(0, 0, 1e-5, 100.0, ss) == 1);
        w.contacts().damage[0] = damage;
        w.particles().position[b].x() -= 20e-6;  // 20 um closer than at bonding: Fn = 20 N
        w.particles().flags[a] |= kFixedVelocity;
        w.particles().flags[b] |= kFixedVelocity;
        w.particles().velocity[b] = Vec3(0, 1e-3, 0);
        w.set_time_step(1e-6);
        double last = 0.0, fn = 0.0;
        for (int s = 0; s < 200000 && w.intact_bond_count() == 1; ++s) {
            last = w.contacts().shear_force[0].norm();
            fn = w.contacts().normal_force[0];
            w.cycle(1);
        }
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
