// The integrator's four-lane path (integrate/sphere_lanes.hpp) against SphereIntegrator run
// particle by particle: on random free spheres (with and without density scaling, kinetic
// energy and a domain box; resting spheres, whose local damping has no sign; a sphere
// moving more than its radius; a NaN force; a sphere leaving the box), the two write the
// same bits into every particle array and leave the same block sums; and the lanes refuse
// a group with a prescribed sphere or a clump member.
#include "engine/core/simd/avx2.hpp"
#include "engine/integrate/central_difference.hpp"
#include "engine/integrate/sphere_lanes.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

using namespace triax;

// Helpers and cases in a named namespace: unity batches put this file beside others with
// file-local helpers of the same names.
namespace sphere_lanes_check {

using test::same_bits;

bool same_bits(const BodySums& a, const BodySums& b) {
    return std::memcmp(&a.kinetic, &b.kinetic, sizeof(double)) == 0 &&
           std::memcmp(&a.damping, &b.damping, sizeof(double)) == 0 &&
           std::memcmp(&a.boundary, &b.boundary, sizeof(double)) == 0 &&
           std::memcmp(&a.body, &b.body, sizeof(double)) == 0 && a.unstable == b.unstable && a.cause == b.cause;
}

struct Pile {
    ParticleArrays pa;
    std::vector<double> inertial_mass, inertial_inertia;
    std::vector<Vec3> f, t;
    std::vector<double> kt, kr;
};

// 16 spheres of 1-2 mm with random forces, torques and velocities; every fourth particle
// at rest in one or more components (sign(v) = 0).
Pile pile(unsigned seed) {
    Pile p;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int q = 0; q < 16; ++q) {
        const int id = p.pa.add(Vec3(u(rng), u(rng), u(rng)) * 5e-3, 1.5e-3 + 0.5e-3 * u(rng), 2650.0, 0);
        p.pa.velocity[id] = Vec3(u(rng), u(rng), u(rng)) * 0.05;
        p.pa.angular_velocity[id] = Vec3(u(rng), u(rng), u(rng)) * 20.0;
        if (q % 4 == 0) p.pa.velocity[id].x() = 0.0;
        if (q % 8 == 0) p.pa.angular_velocity[id].setZero();
        p.pa.external_force[id] = Vec3(u(rng), u(rng), u(rng)) * 1e-3;
        p.f.push_back(Vec3(u(rng), u(rng), u(rng)) * 0.5);
        p.t.push_back(Vec3(u(rng), u(rng), u(rng)) * 1e-4);
        p.kt.push_back(1e5 * (1.5 + u(rng)));
        p.kr.push_back(1e-1 * (1.5 + u(rng)));
    }
    p.inertial_mass.assign(16, 0.0);
    p.inertial_inertia.assign(16, 0.0);
    return p;
}

// The scalar integrator over the pile, then the lanes over a copy: the same bits.
void check_same(Pile scalar, const SphereIntegrator& in) {
    Pile lanes = scalar;
    BodySums s_scalar, s_lanes;
    for (long q = 0; q < 16; ++q)
        in(q, scalar.f[q], scalar.t[q], scalar.kt[q], scalar.kr[q], scalar.pa, scalar.inertial_mass,
           scalar.inertial_inertia, s_scalar);
    for (long q = 0; q < 16; q += 4)
        REQUIRE(integrate_sphere_lanes(in, q, &lanes.f[q], &lanes.t[q], &lanes.kt[q], &lanes.kr[q], lanes.pa,
                                       lanes.inertial_mass, lanes.inertial_inertia, s_lanes));
    CHECK(same_bits(scalar.pa.position, lanes.pa.position));
    CHECK(same_bits(scalar.pa.velocity, lanes.pa.velocity));
    CHECK(same_bits(scalar.pa.angular_velocity, lanes.pa.angular_velocity));
    CHECK(same_bits(scalar.pa.force, lanes.pa.force));
    CHECK(same_bits(scalar.pa.torque, lanes.pa.torque));
    CHECK(same_bits(scalar.inertial_mass, lanes.inertial_mass));
    CHECK(same_bits(scalar.inertial_inertia, lanes.inertial_inertia));
    CHECK(same_bits(s_scalar, s_lanes));
}

SphereIntegrator integrator(bool density_scaling, bool kinetic, bool has_domain) {
    return SphereIntegrator{1e-5, 0.7, Vec3(0.0, 0.0, -9.81), density_scaling, kinetic, has_domain,
                            Vec3::Constant(-5.5e-3), Vec3::Constant(5.5e-3)};
}

TEST_CASE("four spheres across SIMD lanes get the scalar integrator's bits", "[integrate][lanes]") {
    if (!simd::avx2_available()) {
        WARN("this CPU has no AVX2: the lanes are not run");
        return;
    }
    for (unsigned seed : {1u, 2u, 3u}) {
        for (bool scaling : {false, true})
            for (bool kinetic : {false, true})
                for (bool domain : {false, true}) {
                    INFO("seed " << seed << " density scaling " << scaling << " kinetic " << kinetic << " domain "
                                 << domain);
                    const SphereIntegrator in = integrator(scaling, kinetic, domain);
                    check_same(pile(seed), in);

                    // A sphere that moves more than its radius in the step (the second of its four).
                    Pile fast = pile(seed);
                    fast.pa.velocity[5] = Vec3(400.0, 0.0, 0.0);
                    check_same(fast, in);

                    // A NaN force on the third sphere of a group.
                    Pile nan = pile(seed);
                    nan.f[10] = Vec3(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0);
                    check_same(nan, in);

                    // A sphere that leaves the box (when there is one) on the fourth.
                    Pile out = pile(seed);
                    out.pa.position[15] = Vec3(5.49e-3, 0.0, 0.0);
                    out.pa.velocity[15] = Vec3(20.0, 0.0, 0.0);
                    check_same(out, in);
                }
    }
}

TEST_CASE("the lanes refuse a group with a prescribed sphere or a clump member", "[integrate][lanes]") {
    if (!simd::avx2_available()) {
        WARN("this CPU has no AVX2: the lanes are not run");
        return;
    }
    const SphereIntegrator in = integrator(true, true, false);
    for (std::uint8_t flag : {std::uint8_t(kFixedVelocity), std::uint8_t(kClumpMember)}) {
        Pile p = pile(7);
        p.pa.flags[2] = flag;
        const Pile before = p;
        BodySums s;
        CHECK_FALSE(integrate_sphere_lanes(in, 0, &p.f[0], &p.t[0], &p.kt[0], &p.kr[0], p.pa, p.inertial_mass,
                                           p.inertial_inertia, s));
        CHECK(same_bits(before.pa.position, p.pa.position));
        CHECK(same_bits(before.pa.velocity, p.pa.velocity));
        CHECK(same_bits(before.pa.force, p.pa.force));
        CHECK(same_bits(before.inertial_mass, p.inertial_mass));
        CHECK(s.damping == 0.0);
    }
}

}  // namespace sphere_lanes_check
