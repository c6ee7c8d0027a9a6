// Bad input and instabilities are reported as exceptions naming the cause; the
// engine never prints or aborts.
#include "engine/core/world.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>

using namespace triax;

TEST_CASE("bad input names the field", "[engine][errors]") {
    World w;
    CHECK_THROWS_WITH(w.add_sphere(Vec3::Zero(), -1.0, 2650.0), Catch::Contains("radius"));
    CHECK_THROWS_WITH(w.add_sphere(Vec3::Zero(), 1.0, 0.0), Catch::Contains("density"));
    CHECK_THROWS_WITH(w.add_plane_wall(Vec3::Zero(), Vec3::Zero()), Catch::Contains("normal"));
    CHECK_THROWS_WITH(w.set_time_step(-1.0), Catch::Contains("dt"));
    CHECK_THROWS_WITH(w.set_local_damping(1.5), Catch::Contains("alpha"));
    ContactLaw bad;
    bad.kn = -1;
    CHECK_THROWS_WITH(w.set_default_contact_law(bad), Catch::Contains("kn"));
    CHECK_THROWS_WITH(w.add_clump({3}), Catch::Contains("member"));
    w.add_sphere(Vec3::Zero(), 1e-3, 2650.0);
    CHECK_THROWS_WITH(w.cycle(1), Catch::Contains("time step"));
}

TEST_CASE("too large a time step is reported as exploding kinetic energy with the step", "[engine][errors]") {
    World w;
    w.set_default_contact_law(test::linear_law(1e7, 1e7, 0.5));
    w.add_plane_wall(Vec3::Zero(), Vec3::UnitZ());
    const int p = w.add_sphere(Vec3(0, 0, 0.9e-3), 1e-3, 2650.0);
    w.particles().velocity[p] = Vec3(0, 0, -1);
    w.set_local_damping(0.0);
    w.set_time_step(50 * w.critical_time_step());
    try {
        w.cycle(1000);
        FAIL("no error raised");
    } catch (const SimulationError& e) {
        CHECK(e.step() >= 0);
        CHECK(std::string(e.what()).find("exploding kinetic energy") != std::string::npos);
    }
}

TEST_CASE("a particle leaving the domain is reported", "[engine][errors]") {
    World w;
    const int p = w.add_sphere(Vec3::Zero(), 1e-3, 2650.0);
    w.particles().velocity[p] = Vec3(1, 0, 0);
    w.set_domain(Vec3::Constant(-0.01), Vec3::Constant(0.01));
    w.set_time_step(1e-4);
    CHECK_THROWS_WITH(w.cycle(1000), Catch::Contains("escaped the domain") && Catch::Contains("step 100"));
}

TEST_CASE("NaN is reported", "[engine][errors]") {
    World w;
    const int p = w.add_sphere(Vec3::Zero(), 1e-3, 2650.0);
    w.particles().external_force[p] = Vec3(std::nan(""), 0, 0);
    w.set_time_step(1e-4);
    CHECK_THROWS_WITH(w.cycle(10), Catch::Contains("NaN"));
}
