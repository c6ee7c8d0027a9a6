// The time-dependent contact mechanism on a single contact held in place: viscous slip
// relaxes the shear spring and converges below sliding; asperity damage grows only
// above its threshold; dissipation is booked as creep energy.
#include <catch2/catch.hpp>

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

TEST_CASE("viscous slip relaxes the shear force and converges below sliding", "[protocol][creep]") {
    World w = two_spheres();
    auto& c = w.contacts();
    REQUIRE(c.active[0]);
    const double fn = c.normal_force[0];
    c.shear_force[0] = Vec3(0, 0.6 * 0.4 * fn, 0);  // f = 0.6
    creep::RateProcessParams p;
    p.slip_rate_a_m_s = 3e-9;
    p.slip_hardening_length_m = 1e-5;
    p.damage_rate_b1_per_s = 1e-9;
    creep::RateProcessCreep law(p);
    std::vector<double> fs;
    for (int k = 0; k < 40; ++k) {
        law.advance(w, 60.0);
        fs.push_back(c.shear_force[0].norm());
    }
    for (std::size_t k = 1; k < fs.size(); ++k) CHECK(fs[k] <= fs[k - 1]);
    CHECK(fs.back() < 0.6 * 0.4 * fn);
    // Converging: the last ten minutes relax far less than the first ten.
    CHECK((fs[29] - fs[39]) < 0.2 * (0.6 * 0.4 * fn - fs[9]));
    CHECK(w.energy().creep > 0.0);
    CHECK(law.accumulated_slip(0, 1) > 0.0);
}

TEST_CASE("asperity damage grows only above the mobilisation threshold", "[protocol][creep]") {
    creep::RateProcessParams p;
    p.slip_rate_a_m_s = 0.0;  // isolate damage
    p.damage_rate_b1_per_s = 1e-6;
    p.damage_threshold = 0.9;
    for (double f : {0.5, 0.95}) {
        World w = two_spheres();
        auto& c = w.contacts();
        c.shear_force[0] = Vec3(0, f * 0.4 * c.normal_force[0], 0);
        creep::RateProcessParams q = p;
        q.slip_rate_a_m_s = 1e-12;  // a trickle so the contact state is tracked
        creep::RateProcessCreep law(q);
        const auto s = law.advance(w, 3600.0);
        if (f < 0.9) CHECK(s.mean_asperity_damage == 0.0);
        else CHECK(s.mean_asperity_damage > 0.0);
    }
}
