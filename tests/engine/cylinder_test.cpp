// Cylinder wall: a sphere inside hits the lateral wall elastically (contact duration
// pi sqrt(m / kn), rebound speed), pushes it outward, and a shrinking wall does
// boundary work on the particles.
#include "engine/core/world.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>

using namespace triax;

TEST_CASE("sphere inside a cylinder wall: elastic impact on the lateral surface", "[engine][cylinder]") {
    World w;
    const double r = 0.005, R = 0.05, kn = 1e5, v0 = 0.3;
    w.set_default_contact_law(test::linear_law(kn, kn, 0.0));
    const int c = w.add_cylinder_wall(Vec3(0, 0, 0), Vec3::UnitZ(), R, 0.1);
    const int p = w.add_sphere(Vec3(R - r - 1e-4, 0, 0.05), r, 2650.0);
    w.particles().velocity[p] = Vec3(v0, 0, 0);
    w.set_local_damping(0.0);
    const double m = test::sphere_mass(r, 2650.0);
    w.set_time_step(test::kPi * std::sqrt(m / kn) / 2000.0);
    long in_contact = 0;
    bool touched = false;
    double peak_radial = 0.0, peak_fx = 0.0;
    for (int s = 0; s < 100000; ++s) {
        w.cycle(1);
        const bool touching = w.cylinder_wall(c).contact_count > 0;
        if (touching) {
            ++in_contact;
            touched = true;
            peak_radial = std::max(peak_radial, w.cylinder_wall(c).radial_force);
            peak_fx = std::max(peak_fx, w.cylinder_wall(c).force.x());
        }
        if (touched && !touching) break;
    }
    CHECK(in_contact * w.time_step() == Approx(test::kPi * std::sqrt(m / kn)).epsilon(0.01));
    CHECK(w.particles().velocity[p].x() == Approx(-v0).epsilon(0.01));
    CHECK(peak_radial == Approx(v0 * std::sqrt(m * kn)).epsilon(0.01));  // k * max overlap
    CHECK(peak_fx == Approx(peak_radial).epsilon(1e-9));                 // pushed outward along +x
}

TEST_CASE("a shrinking cylinder does positive boundary work and the books close", "[engine][cylinder][energy]") {
    World w;
    const double R = 0.0108;  // 0.3 mm gap outside the ring of spheres
    w.set_default_contact_law(test::linear_law(1e4, 1e4, 0.3));
    const int c = w.add_cylinder_wall(Vec3(0, 0, 0), Vec3::UnitZ(), R, 0.01);
    w.add_plane_wall(Vec3(0, 0, 0), Vec3::UnitZ());
    w.add_plane_wall(Vec3(0, 0, 0.01), -Vec3::UnitZ());
    test::Rng rng(9);
    for (int k = 0; k < 16; ++k) {  // ring of 16 spheres of 3 mm on a 9 mm radius: no overlap
        const double a = 2 * test::kPi * k / 16.0;
        w.add_sphere(Vec3(0.009 * std::cos(a), 0.009 * std::sin(a), 0.002 + 0.006 * rng.uniform()), 0.0015, 2650.0);
    }
    w.set_time_step(w.critical_time_step(0.2));
    w.cylinder_wall(c).radial_velocity = -0.02;
    w.cycle(4000);  // about 0.7 mm of travel: 0.4 mm into the ring
    w.cylinder_wall(c).radial_velocity = 0.0;
    w.cycle(5000);
    const EnergyLedger& e = w.energy();
    REQUIRE(e.boundary_work > 0);
    CHECK(e.slip + e.damping > 0);  // the wall pushed the spheres, they dissipated it
    CHECK(std::abs(e.imbalance()) <= 0.01 * e.boundary_work);
}
