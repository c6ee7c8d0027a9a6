// The shortcuts inside the time step must give bitwise what their plain forms give, for
// every input including zeros, subnormals, infinities and NaN: the sqrt-free norm
// comparisons of the contact law (|x| >= s and |x| > s from x^2), the sqrt-free stability
// check (moved more than one radius in one step), and the branch-free sign of local
// damping (sign(v) in {-1, 0, +1}).
#include "engine/contact/linear.hpp"
#include "engine/core/world.hpp"
#include "engine/integrate/local_damping.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace triax;

TEST_CASE("sqrt-free norm comparisons equal the plain sqrt comparisons bitwise", "[engine][contact]") {
    test::Rng rng(17);
    long near = 0, checked = 0;
    auto check = [&](double x2, double s) {
        ++checked;
        const bool ge = std::sqrt(x2) >= s, gt = std::sqrt(x2) > s;
        if (LinearContact::norm_at_least(x2, s) != ge || LinearContact::norm_above(x2, s) != gt) {
            FAIL_CHECK("x2 = " << x2 << ", s = " << s);
        }
    };
    for (int k = 0; k < 200000; ++k) {
        const double s = std::pow(10.0, -6.0 + 12.0 * rng.uniform());
        // Squares around s^2, within a few ulps of it (the hard cases) and far from it.
        const double s2 = s * s;
        double x2 = s2;
        const int ulps = static_cast<int>(rng.uniform() * 80.0) - 40;
        for (int u = 0; u < std::abs(ulps); ++u) x2 = std::nextafter(x2, ulps > 0 ? 2.0 * s2 : 0.0);
        check(x2, s);
        check(s2 * (0.5 + rng.uniform()), s);
        // The square of a number a few ulps from s (sqrt(x2) rounds to s or a neighbour).
        double r = s;
        for (int u = 0; u < std::abs(ulps) % 8; ++u) r = std::nextafter(r, ulps > 0 ? 2.0 * s : 0.0);
        check(r * r, s);
        near += std::sqrt(r * r) == s;
    }
    // Edge values: zero, negative or non-finite strengths and squares.
    const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
    for (double s : {0.0, -1.0, 1e-300, 1.0, 1e200, inf, nan})
        for (double x2 : {0.0, 1e-300, 1.0, 1e300, inf, nan}) check(x2, s);
    CHECK(near > 1000);  // the hard cases were really met
    CHECK(checked > 600000);
}

TEST_CASE("branch-free sign of local damping equals the conditional form", "[engine][damping]") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    CHECK(sign_of(2.5) == 1.0);
    CHECK(sign_of(-1e-300) == -1.0);
    CHECK(sign_of(0.0) == 0.0);
    CHECK(sign_of(-0.0) == 0.0);
    CHECK(sign_of(nan) == 0.0);
    // At the edges: infinities and subnormals keep their sign, NaN of either sign gives 0,
    // and every zero result is +0.0, as (v > 0) - (v < 0) gives (checked with signbit,
    // since -0.0 == 0.0 holds and the equalities above cannot tell them apart).
    const double inf = std::numeric_limits<double>::infinity(), tiny = std::numeric_limits<double>::denorm_min();
    CHECK(sign_of(inf) == 1.0);
    CHECK(sign_of(-inf) == -1.0);
    CHECK(sign_of(tiny) == 1.0);
    CHECK(sign_of(-tiny) == -1.0);
    CHECK(sign_of(-nan) == 0.0);
    CHECK_FALSE(std::signbit(sign_of(0.0)));
    CHECK_FALSE(std::signbit(sign_of(-0.0)));
    CHECK_FALSE(std::signbit(sign_of(nan)));
    test::Rng rng(5);
    for (int k = 0; k < 1000; ++k) {
        const Vec3 f(rng.uniform() - 0.5, rng.uniform() - 0.5, 0.0);
        const Vec3 v(rng.uniform() - 0.5, 0.0, -(rng.uniform() - 0.5));
        const Vec3 fd = local_damping_force(f, v, 0.7);
        for (int a = 0; a < 3; ++a) {
            const double plain = f[a] - 0.7 * std::abs(f[a]) * (v[a] > 0.0 ? 1.0 : (v[a] < 0.0 ? -1.0 : 0.0));
            CHECK(fd[a] == plain);
        }
    }
}

// The stability check ("moved more than its radius in one step") skips its sqrt when the
// step is clearly shorter; it must still fire just above the radius and not just below.
TEST_CASE("the sqrt-free stability check fires at one radius per step, not below", "[engine][errors]") {
    const double r = 1e-3, dt = 1e-5;
    for (const double ratio : {0.999999, 1.000001, 0.5, 3.0}) {
        World w;
        w.set_default_contact_law(test::linear_law(1e4, 1e4, 0.5));
        const int p = w.add_sphere(Vec3::Zero(), r, 2650.0);
        w.set_time_step(dt);
        w.particles().velocity[p] = Vec3(0.6, -0.8, 0.0) * (ratio * r / dt);  // |v| dt = ratio r
        if (ratio > 1.0) {
            CHECK_THROWS_AS(w.cycle(1), SimulationError);
        } else {
            CHECK_NOTHROW(w.cycle(3));
        }
    }
}
