// Chung & Ooi (2011) test 6 with the linear model: oblique impact of a sphere on a
// flat wall, rebound angular velocity against the incidence angle.
// With ks / kn = 2/7 the tangential and normal oscillations share one frequency
// (omega_t^2 = 3.5 ks / m = kn / m), which gives two closed-form regimes:
//   tan(theta) <= 3.5 mu : the contact sticks all along, w = (10/7) v_t / R
//   tan(theta) >= 7 mu   : it slides all along,       w = 5 mu v_n / R
// (derivation in docs/engine.md, "Verification").
#include "engine/core/world.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>

using namespace triax;

namespace {

double rebound_spin(double tan_theta, double mu) {
    World w;
    const double r = 0.01, rho = 2650.0, kn = 1e6, vn = 0.5;
    w.set_default_contact_law(test::linear_law(kn, kn * 2.0 / 7.0, mu));
    w.add_plane_wall(Vec3::Zero(), Vec3::UnitZ());
    const int p = w.add_sphere(Vec3(0, 0, r + 1e-5), r, rho);
    w.particles().velocity[p] = Vec3(vn * tan_theta, 0, -vn);
    w.set_local_damping(0.0);
    const double m = test::sphere_mass(r, rho);
    w.set_time_step(test::kPi * std::sqrt(m / kn) / 4000.0);
    bool touched = false;
    for (int s = 0; s < 100000; ++s) {
        w.cycle(1);
        const bool touching = w.plane_wall(0).contact_count > 0;
        touched = touched || touching;
        if (touched && !touching) break;
    }
    return w.particles().angular_velocity[p].y();
}

}  // namespace

TEST_CASE("oblique impact, sticking regime: w = (10/7) v_t / R", "[engine][impact][oblique]") {
    const double mu = 0.3, r = 0.01, vn = 0.5;
    for (double f : {0.25, 0.5, 0.9}) {
        const double tan_theta = f * 3.5 * mu;
        CHECK(rebound_spin(tan_theta, mu) == Approx(10.0 / 7.0 * vn * tan_theta / r).epsilon(0.01));
    }
}

TEST_CASE("oblique impact, sliding regime: w = 5 mu v_n / R", "[engine][impact][oblique]") {
    const double mu = 0.3, r = 0.01, vn = 0.5;
    for (double f : {1.1, 2.0, 4.0}) {
        const double tan_theta = f * 7.0 * mu;
        CHECK(rebound_spin(tan_theta, mu) == Approx(5.0 * mu * vn / r).epsilon(0.01));
    }
}

TEST_CASE("oblique impact, transition: spin between the two regimes and monotone", "[engine][impact][oblique]") {
    const double mu = 0.3;
    double last = 0.0;
    for (double t = 0.2; t <= 4.0; t += 0.2) {
        const double w = rebound_spin(t, mu);
        CHECK(w >= last - 1e-9);  // grows with the angle until sliding, then stays
        last = std::max(last, w);
    }
}
