// Chung & Ooi (2011) tests 1-2 with the linear model: normal elastic impact of a
// sphere on a wall and of two spheres (contact duration pi sqrt(m_eff / kn), rebound
// velocity), and impact with damping against the analytic restitution coefficient.
#include "engine/core/world.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>

using namespace triax;
using triax::test::kPi;

namespace {

struct ImpactResult {
    double duration;        // s
    double rebound_speed;   // m/s
};

// Runs until the contact has opened again; counts the steps with an active contact.
ImpactResult sphere_wall_impact(double kn, double v0, double alpha, double beta) {
    World w;
    const double r = 0.01, rho = 2650.0;
    ContactLaw law = test::linear_law(kn, kn, 0.0);
    law.normal_damping_ratio = beta;
    w.set_default_contact_law(law);
    w.add_plane_wall(Vec3::Zero(), Vec3::UnitZ());
    const int p = w.add_sphere(Vec3(0, 0, r + 1e-4), r, rho);
    w.particles().velocity[p] = Vec3(0, 0, -v0);
    w.set_local_damping(alpha);
    const double m = test::sphere_mass(r, rho);
    const double tc = kPi * std::sqrt(m / kn);
    w.set_time_step(tc / 2000.0);
    long in_contact = 0;
    bool touched = false;
    for (int s = 0; s < 200000; ++s) {
        w.cycle(1);
        const bool touching = w.plane_wall(0).contact_count > 0;
        if (touching) { ++in_contact; touched = true; }
        if (touched && !touching) break;
    }
    return {in_contact * w.time_step(), w.particles().velocity[p].z()};
}

}  // namespace

TEST_CASE("normal elastic impact sphere-wall: duration and rebound", "[engine][impact]") {
    const double kn = 1e5, v0 = 0.5;
    const double m = test::sphere_mass(0.01, 2650.0);
    const ImpactResult res = sphere_wall_impact(kn, v0, 0.0, 0.0);
    CHECK(res.duration == Approx(kPi * std::sqrt(m / kn)).epsilon(0.01));
    CHECK(res.rebound_speed == Approx(v0).epsilon(0.01));
}

TEST_CASE("normal elastic impact sphere-sphere: duration and rebound", "[engine][impact]") {
    World w;
    const double r1 = 0.01, r2 = 0.015, rho = 2650.0, kn = 2e5, v = 0.3;
    w.set_default_contact_law(test::linear_law(kn, kn, 0.0));
    const int a = w.add_sphere(Vec3(0, 0, 0), r1, rho);
    const int b = w.add_sphere(Vec3(r1 + r2 + 2e-4, 0, 0), r2, rho);
    w.particles().velocity[a] = Vec3(v, 0, 0);
    w.particles().velocity[b] = Vec3(-v, 0, 0);
    w.set_local_damping(0.0);
    const double m1 = test::sphere_mass(r1, rho), m2 = test::sphere_mass(r2, rho);
    const double m_eff = m1 * m2 / (m1 + m2);
    const double tc = kPi * std::sqrt(m_eff / kn);
    w.set_time_step(tc / 2000.0);
    long in_contact = 0;
    bool touched = false;
    for (int s = 0; s < 200000; ++s) {
        w.cycle(1);
        const bool touching = w.active_contact_count() > 0;
        if (touching) { ++in_contact; touched = true; }
        if (touched && !touching) break;
    }
    CHECK(in_contact * w.time_step() == Approx(tc).epsilon(0.01));
    // Elastic: the relative normal velocity reverses; momentum is conserved.
    const Vec3 va = w.particles().velocity[a], vb = w.particles().velocity[b];
    CHECK((vb.x() - va.x()) == Approx(2 * v).epsilon(0.01));
    CHECK(m1 * va.x() + m2 * vb.x() == Approx(m1 * v - m2 * v).epsilon(1e-9));
}

TEST_CASE("impact with local damping: e = sqrt((1 - alpha) / (1 + alpha))", "[engine][impact][damping]") {
    for (double alpha : {0.1, 0.3, 0.7}) {
        const ImpactResult res = sphere_wall_impact(1e5, 0.5, alpha, 0.0);
        CHECK(res.rebound_speed / 0.5 == Approx(std::sqrt((1 - alpha) / (1 + alpha))).epsilon(0.01));
    }
}

TEST_CASE("impact with a viscous normal dashpot: e = exp(-beta pi / sqrt(1 - beta^2))", "[engine][impact][damping]") {
    for (double beta : {0.05, 0.2, 0.4}) {
        const ImpactResult res = sphere_wall_impact(1e5, 0.5, 0.0, beta);
        const double e = std::exp(-beta * kPi / std::sqrt(1 - beta * beta));
        CHECK(res.rebound_speed / 0.5 == Approx(e).epsilon(0.01));
    }
}
