// The energy books close: boundary work = strain + kinetic + slip + damping (+ bond,
// dashpot) within 1% over a load-unload cycle, and with no dissipation the stored
// energy is conserved.
#include "engine/core/world.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace triax;

namespace {

constexpr int kSide = 8;
constexpr double kRmin = 0.6e-3, kRmax = 1.0e-3;

World box_world(double mu, double alpha, std::uint64_t seed) {
    World w;
    w.set_default_contact_law(test::linear_law(2e4, 1e4, mu));
    const double L = kSide * 2.05 * kRmax;
    test::add_box(w, L);
    for (const auto& s : test::lattice_spheres(kSide, kRmin, kRmax, seed)) w.add_sphere(s.x, s.r, 2650.0);
    w.set_local_damping(alpha);
    w.set_time_step(0.2 * std::sqrt(test::sphere_mass(kRmin, 2650.0) / 2e4));
    return w;
}

}  // namespace

TEST_CASE("energy balance over a load-unload cycle closes within 1%", "[engine][energy]") {
    World w = box_world(0.4, 0.7, 21);
    // Load: the top wall and one side wall close in; unload: they back off again.
    const double v = 0.05;  // m/s
    const int top = 5, side = 1;
    w.plane_wall(top).velocity = Vec3(0, 0, -v);
    w.plane_wall(side).velocity = Vec3(-v, 0, 0);
    long steps = 0;
    while (w.plane_wall(top).normal_stress(1.0) * 1.0 < 1e-9 || w.energy().strain < 2e-6) {
        w.cycle(100);
        steps += 100;
        REQUIRE(steps < 400000);
    }
    w.cycle(steps / 4);  // load further into the contact network
    const EnergyLedger loaded = w.energy();
    REQUIRE(loaded.strain > 0);
    REQUIRE(loaded.slip > 0);
    REQUIRE(loaded.damping > 0);
    CHECK(std::abs(loaded.imbalance()) <= 0.01 * loaded.boundary_work);

    w.plane_wall(top).velocity = Vec3(0, 0, v);
    w.plane_wall(side).velocity = Vec3(v, 0, 0);
    w.cycle(steps / 2);
    w.plane_wall(top).velocity.setZero();
    w.plane_wall(side).velocity.setZero();
    w.cycle(2000);
    const EnergyLedger& e = w.energy();
    CHECK(e.strain < 0.5 * loaded.strain);  // the assembly was unloaded
    CHECK(std::abs(e.imbalance()) <= 0.01 * e.boundary_work);
    CHECK(e.boundary_work == Approx(e.strain + e.kinetic + e.slip + e.damping + e.dashpot + e.bond_strain + e.bond_break).epsilon(0.01));
}

TEST_CASE("without friction or damping the stored energy is conserved", "[engine][energy]") {
    World w = box_world(0.0, 0.0, 4);
    for (std::size_t p = 0; p < w.particle_count(); ++p)
        w.particles().velocity[p] = Vec3(std::sin(1.0 * p), std::cos(2.0 * p), std::sin(3.0 * p)) * 0.3;
    w.cycle(1);
    const double e0 = w.energy().stored();
    w.cycle(20000);
    REQUIRE(w.energy().slip == 0.0);
    CHECK(w.energy().stored() == Approx(e0).epsilon(0.01));
}

TEST_CASE("applied particle forces and gravity are booked as input", "[engine][energy]") {
    World w;
    w.set_default_contact_law(test::linear_law(1e4, 1e4, 0.5));
    w.add_plane_wall(Vec3::Zero(), Vec3::UnitZ());
    const int p = w.add_sphere(Vec3(0, 0, 0.01), 0.002, 2650.0);
    w.set_gravity(Vec3(0, 0, -9.81));
    w.particles().external_force[p] = Vec3(0, 0, -1e-3);
    w.set_time_step(w.critical_time_step(0.2));
    w.cycle(100000);  // falls, bounces, settles under local damping
    const EnergyLedger& e = w.energy();
    REQUIRE(e.body_force_work > 0);
    REQUIRE(e.boundary_work > 0);
    CHECK(std::abs(e.imbalance()) <= 0.01 * e.input());
}

// The stored energies are booked on the last step of each cycle() call only (world_step.cpp,
// StepState): after any call they must be the springs' and bodies' energy of that step,
// and equal to what one-step calls give.
TEST_CASE("state energies after a multi-step cycle() are those of its last step", "[engine][energy]") {
    World a = box_world(0.4, 0.7, 21), b = box_world(0.4, 0.7, 21);
    a.plane_wall(5).velocity = b.plane_wall(5).velocity = Vec3(0, 0, -0.05);
    a.cycle(6000);
    for (int k = 0; k < 6000; ++k) b.cycle(1);
    REQUIRE(a.energy().strain > 0.0);
    REQUIRE(a.energy().kinetic > 0.0);
    CHECK(a.energy().strain == b.energy().strain);
    CHECK(a.energy().kinetic == b.energy().kinetic);
    CHECK(a.energy().slip == b.energy().slip);
    // Independently from the contact store and the velocities (true masses: no scaling).
    double strain = 0.0, kinetic = 0.0;
    const ContactStore& c = a.contacts();
    for (std::size_t k = 0; k < c.size(); ++k) {
        if (!c.active[k]) continue;
        const ContactLaw& law = a.contact_law_of(k);
        strain += 0.5 * c.normal_force[k] * c.normal_force[k] / law.kn + 0.5 * c.shear_force[k].squaredNorm() / law.ks;
    }
    const WallContactStore& wc = a.wall_contacts();
    for (std::size_t k = 0; k < wc.size(); ++k) {
        if (!wc.active[k]) continue;
        const ContactLaw& law = a.wall_contact_law_of(k);
        strain += 0.5 * wc.normal_force[k] * wc.normal_force[k] / law.kn + 0.5 * wc.shear_force[k].squaredNorm() / law.ks;
    }
    const ParticleArrays& pa = a.particles();
    for (std::size_t p = 0; p < pa.size(); ++p)
        kinetic += 0.5 * pa.mass[p] * pa.velocity[p].squaredNorm() + 0.5 * pa.inertia[p] * pa.angular_velocity[p].squaredNorm();
    CHECK(a.energy().strain == Approx(strain).epsilon(1e-12));
    CHECK(a.energy().kinetic == Approx(kinetic).epsilon(1e-12));
    // A kinetic-energy limit is checked on every step, not only on the last of a call:
    // triple every velocity (9x the kinetic energy) under a limit of twice the old one.
    World d = box_world(0.4, 0.7, 21);
    d.plane_wall(5).velocity = Vec3(0, 0, -0.05);
    d.cycle(6000);
    d.set_max_kinetic_energy(2.0 * d.energy().kinetic);
    for (auto& v : d.particles().velocity) v *= 3.0;
    try {
        d.cycle(5);
        FAIL("no SimulationError");
    } catch (const SimulationError& e) {
        CHECK(e.step() == 6000);  // the first step of the call, not its last
    }
}
