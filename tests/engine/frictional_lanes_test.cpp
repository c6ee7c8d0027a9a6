// The contact pass's four-lane kernel (core/step/frictional_lanes.hpp) against the scalar
// path: on a random pile of overlapping spheres with every kind of slot (fresh and loaded
// shear histories, histories tilted out of the contact plane, sliding contacts, bonded
// slots, a law with a dashpot, slots whose creep offset opens them, apart slots), the
// contact pass with the lanes and the one without write the same bits into every slot and
// return the same energy sums; and the kernel takes the plain frictional slots and refuses
// the others.
#include "engine/contact/linear.hpp"
#include "engine/core/step/contact_forces.hpp"
#include "engine/core/step/frictional_lanes.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>

#include <cstring>
#include <random>
#include <vector>

using namespace triax;

namespace {

// The linear law with the lanes switched off: the scalar path only.
struct ScalarOnlyLinearContact : LinearContact {
    static constexpr bool kRunsFrictionalLanes = false;
};

using test::same_bits;

struct LanesPile {
    ParticleArrays pa;
    ContactStore c;
    std::vector<LinearContact::Params> params;
};

// n spheres of 1-2 mm in a 12 mm box, every pair within reach as a slot (sorted by (i, j)).
LanesPile lanes_pile(unsigned seed) {
    LanesPile p;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int n = 150;
    for (int q = 0; q < n; ++q) {
        const int id = p.pa.add(Vec3(12e-3 * u(rng), 12e-3 * u(rng), 12e-3 * u(rng)), 1e-3 * (1.0 + u(rng)), 2650.0, 0);
        p.pa.velocity[id] = Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5) * 0.1;
        p.pa.angular_velocity[id] = Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5) * 50.0;
    }
    ContactLaw plain;
    plain.kn = 2e5;
    plain.ks = 1e5;
    plain.friction = 0.4;
    ContactLaw damped = plain;
    damped.normal_damping_ratio = 0.2;
    p.params = {LinearContact::Params::from(plain), LinearContact::Params::from(damped)};
    for (int a = 0; a < n; ++a)
        for (int b = a + 1; b < n; ++b) {
            const double reach = p.pa.radius[a] + p.pa.radius[b] + 2e-4;
            if ((p.pa.position[b] - p.pa.position[a]).squaredNorm() > reach * reach) continue;
            const long k = static_cast<long>(p.c.size());
            p.c.resize(k + 1);
            p.c.reset_history(k);
            p.c.force_on_j[k].setZero();
            p.c.torque_on_i[k].setZero();
            p.c.torque_on_j[k].setZero();
            p.c.contact_point[k].setZero();
            p.c.overlap[k] = 0.0;
            p.c.i[k] = a;
            p.c.j[k] = b;
            p.c.law[k] = u(rng) < 0.05 ? 1 : 0;
            const double kind = u(rng);
            const Vec3 n_ab = (p.pa.position[b] - p.pa.position[a]).normalized();
            const Vec3 any(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
            const Vec3 tangent = any - n_ab * n_ab.dot(any);
            if (kind < 0.25) {
                // fresh contact: no shear history
            } else if (kind < 0.55) {
                p.c.shear_force[k] = tangent * 2.0;  // loaded, in the plane
                p.c.active[k] = 1;
            } else if (kind < 0.75) {
                p.c.shear_force[k] = any * 3.0;  // tilted out of the plane
                p.c.active[k] = 1;
            } else if (kind < 0.85) {
                p.c.shear_force[k] = tangent * 1e4;  // far beyond the slider: slides
                p.c.active[k] = 1;
            } else if (kind < 0.90) {
                p.c.bonded[k] = 1;  // bonded: the scalar path
                p.c.bond_normal_strength[k] = 10.0;
                p.c.bond_shear_strength[k] = 10.0;
                p.c.active[k] = 1;
            } else if (kind < 0.95) {
                p.c.plastic_overlap[k] = 5e-4;  // the creep offset opens it
                p.c.active[k] = 1;
            } else {
                p.c.shear_force[k] = n_ab * 2.0;  // along the normal: turns to zero
                p.c.active[k] = 1;
            }
        }
    return p;
}

}  // namespace

TEST_CASE("frictional lanes: the contact pass writes the scalar path's bits", "[engine][contact][lanes]") {
    // Without AVX2 both passes run the scalar path (and must still agree).
    if (!simd::avx2_available()) WARN("this CPU has no AVX2: the lanes are not run");
    for (const unsigned seed : {1u, 2u, 3u}) {
        LanesPile lanes = lanes_pile(seed);
        LanesPile scalar = lanes;
        REQUIRE(lanes.c.size() > 200);
        const long blocks = step::block_count(static_cast<long>(lanes.c.size()), step::kContactBlock);
        for (int step_no = 0; step_no < 3; ++step_no)
            for (long b = 0; b < blocks; ++b) {
                const bool state_energy = step_no == 2;
                const ContactSums with = step::ContactForces<LinearContact>::block(lanes.c, lanes.pa, lanes.params, 1e-6, b,
                                                                                   false, state_energy);
                const ContactSums without = step::ContactForces<ScalarOnlyLinearContact>::block(
                    scalar.c, scalar.pa, scalar.params, 1e-6, b, false, state_energy);
                CHECK(std::memcmp(&with.slip, &without.slip, sizeof(double)) == 0);
                CHECK(std::memcmp(&with.strain, &without.strain, sizeof(double)) == 0);
                CHECK(std::memcmp(&with.dashpot, &without.dashpot, sizeof(double)) == 0);
                CHECK(with.broke_tension == without.broke_tension);
                CHECK(with.broke_shear == without.broke_shear);
            }
        CHECK(same_bits(lanes.c.active, scalar.c.active));
        CHECK(same_bits(lanes.c.normal_force, scalar.c.normal_force));
        CHECK(same_bits(lanes.c.shear_force, scalar.c.shear_force));
        CHECK(same_bits(lanes.c.rolling_moment, scalar.c.rolling_moment));
        CHECK(same_bits(lanes.c.bonded, scalar.c.bonded));
        CHECK(same_bits(lanes.c.force_on_j, scalar.c.force_on_j));
        CHECK(same_bits(lanes.c.torque_on_i, scalar.c.torque_on_i));
        CHECK(same_bits(lanes.c.torque_on_j, scalar.c.torque_on_j));
        CHECK(same_bits(lanes.c.contact_point, scalar.c.contact_point));
        CHECK(same_bits(lanes.c.overlap, scalar.c.overlap));
    }
}

TEST_CASE("frictional lanes: plain frictional slots go through, bonded and damped ones do not",
          "[engine][contact][lanes]") {
    if (!simd::avx2_available()) {
        WARN("this CPU has no AVX2: the contact pass runs the scalar path only, the kernel is not called");
        return;
    }
    LanesPile p = lanes_pile(4);
    // Four touching, unbonded slots of the plain law whose creep offset leaves them closed.
    std::vector<long> plain, bonded;
    for (long k = 0; k < static_cast<long>(p.c.size()); ++k) {
        const double reach = p.pa.radius[p.c.i[k]] + p.pa.radius[p.c.j[k]] - p.c.plastic_overlap[k];
        const bool touching = (p.pa.position[p.c.j[k]] - p.pa.position[p.c.i[k]]).squaredNorm() < reach * reach;
        if (!touching || p.c.law[k] != 0) continue;
        if (p.c.bonded[k]) bonded.push_back(k);
        else plain.push_back(k);
    }
    REQUIRE(plain.size() >= 4);
    REQUIRE(!bonded.empty());
    ContactSums sums;
    long four[step::kLaneCount] = {plain[0], plain[1], plain[2], plain[3]};
    CHECK(step::frictional_lanes(p.c, p.pa, p.params.data(), 1e-6, four, true, sums));
    CHECK(sums.strain > 0.0);  // the four springs' stored energy
    for (int l = 0; l < step::kLaneCount; ++l) {
        CHECK(p.c.active[four[l]] == 1);
        CHECK(p.c.normal_force[four[l]] > 0.0);
    }
    four[2] = bonded[0];
    const ContactStore before = p.c;
    const ContactSums sums_before = sums;
    CHECK_FALSE(step::frictional_lanes(p.c, p.pa, p.params.data(), 1e-6, four, true, sums));
    CHECK(same_bits(p.c.force_on_j, before.force_on_j));  // nothing written
    CHECK(sums.strain == sums_before.strain);
    p.c.law[bonded[0]] = 1;
    p.c.bonded[bonded[0]] = 0;  // unbonded, but its law has a dashpot
    CHECK_FALSE(step::frictional_lanes(p.c, p.pa, p.params.data(), 1e-6, four, false, sums));
}
