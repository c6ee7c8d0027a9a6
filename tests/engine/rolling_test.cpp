// Rolling resistance (rrlinear-like): a sphere rolling on a plane under gravity with
// rolling friction mu_r decelerates at a = mu_r g / 1.4 (solid sphere, rolling without
// slip: (I + m R^2) dw/dt = -mu_r R m g); without it, it keeps rolling.
#include "engine/core/world.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>

using namespace triax;

namespace {

struct Roll {
    double deceleration;
    double final_speed;
};

Roll roll(double mu_r) {
    World w;
    const double r = 0.005, g = 9.81, v0 = 0.05;
    ContactLaw law = test::linear_law(1e5, 1e5, 0.8);
    law.rolling_friction = mu_r;
    law.normal_damping_ratio = 0.7;
    w.set_default_contact_law(law);
    w.add_plane_wall(Vec3::Zero(), Vec3::UnitZ());
    const double m = test::sphere_mass(r, 2650.0);
    const int p = w.add_sphere(Vec3(0, 0, r - m * g / 1e5), r, 2650.0);
    w.set_gravity(Vec3(0, 0, -g));
    w.set_local_damping(0.0);
    w.set_time_step(w.critical_time_step(0.2));
    w.cycle(5000);  // settle
    w.particles().velocity[p] = Vec3(v0, 0, 0);
    w.particles().angular_velocity[p] = Vec3(0, v0 / r, 0);
    w.cycle(2000);
    const double t1 = w.time(), v1 = w.particles().velocity[p].x();
    w.cycle(4000);  // stays well before the stop (v0 / a ~ 0.14 s)
    const double t2 = w.time(), v2 = w.particles().velocity[p].x();
    w.cycle(400000);
    return {(v1 - v2) / (t2 - t1), w.particles().velocity[p].x()};
}

}  // namespace

TEST_CASE("rolling resistance decelerates a rolling sphere at mu_r g / 1.4", "[engine][rolling]") {
    const double mu_r = 0.05;
    const Roll res = roll(mu_r);
    CHECK(res.deceleration == Approx(mu_r * 9.81 / 1.4).epsilon(0.01));
    CHECK(std::abs(res.final_speed) < 1e-4);  // it stops and stays
}

TEST_CASE("without rolling resistance a sphere keeps rolling", "[engine][rolling]") {
    const Roll res = roll(0.0);
    CHECK(std::abs(res.deceleration) < 1e-3);
    CHECK(res.final_speed == Approx(0.05).epsilon(0.01));
}
