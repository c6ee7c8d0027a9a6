// A three-sphere clump resting on a plane under tilted gravity: it slides with
// a = g (sin(theta) - mu cos(theta)) when tan(theta) > mu and stays put when below.
// Local damping is off (it would scale the acceleration); a normal dashpot kills the
// initial bounce.
#include "engine/core/world.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>

using namespace triax;

namespace {

struct SlideResult {
    double acceleration;  // m/s^2 along the slope, measured after settling
    double travel;        // m along the slope
};

SlideResult slide(double theta, double mu) {
    World w;
    const double r = 0.005, rho = 2650.0, g = 9.81;
    ContactLaw law = test::linear_law(1e5, 1e5, mu);
    law.normal_damping_ratio = 0.7;
    w.set_default_contact_law(law);
    w.add_plane_wall(Vec3::Zero(), Vec3::UnitZ());
    const int a = w.add_sphere(Vec3(0, 0, r), r, rho);
    const int b = w.add_sphere(Vec3(2.2 * r, 0, r), r, rho);
    const int c = w.add_sphere(Vec3(1.1 * r, 1.9 * r, r), r, rho);
    const int k = w.add_clump({a, b, c});
    w.set_local_damping(0.0);
    w.set_time_step(w.critical_time_step(0.2));
    w.set_gravity(Vec3(0, 0, -g));
    w.cycle(20000);  // settle on the plane
    w.set_gravity(Vec3(g * std::sin(theta), 0, -g * std::cos(theta)));
    const double x0 = w.clump(k).position.x();
    w.cycle(2000);
    const double t1 = w.time(), v1 = w.clump(k).velocity.x();
    w.cycle(20000);
    const double t2 = w.time(), v2 = w.clump(k).velocity.x();
    return {(v2 - v1) / (t2 - t1), w.clump(k).position.x() - x0};
}

}  // namespace

TEST_CASE("clump on an incline slides above tan(theta) = mu", "[engine][incline]") {
    const double mu = 0.4, g = 9.81;
    for (double theta_deg : {25.0, 35.0, 45.0}) {
        const double theta = theta_deg * test::kPi / 180.0;
        const SlideResult res = slide(theta, mu);
        CHECK(res.acceleration == Approx(g * (std::sin(theta) - mu * std::cos(theta))).epsilon(0.01));
    }
}

TEST_CASE("clump on an incline sticks below tan(theta) = mu", "[engine][incline]") {
    const double mu = 0.4;
    for (double theta_deg : {10.0, 20.0}) {
        const SlideResult res = slide(theta_deg * test::kPi / 180.0, mu);
        CHECK(std::abs(res.acceleration) < 1e-3);
        CHECK(std::abs(res.travel) < 1e-5);  // elastic shear of the springs only
    }
}
