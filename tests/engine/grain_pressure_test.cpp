// Pressure on the outermost grains (boundary/grain_pressure.hpp): the radial force it applies
// is the pressure times the envelope's lateral area, on the grains at the surface only, along
// the inward radial; a grain that sticks out takes its cells' share; the enclosed volume is
// the envelope's.
#include "engine/boundary/grain_pressure.hpp"
#include "engine/core/world.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace triax;

namespace {
// Rings of touching spheres of radius a whose outer surface is at R, n_rows rows stacked a
// diameter apart from z = 0, and one sphere on the axis at mid-height (shielded by the rings).
struct Rings {
    World world;
    int n_ring = 0, n_rows = 0;
    double R = 0.025, a = 0.0025;
    int axis_sphere = -1;
    explicit Rings(int rows) : n_rows(rows) {
        const double rc = R - a;
        n_ring = static_cast<int>(std::floor(test::kPi / std::asin(a / rc)));
        for (int iz = 0; iz < n_rows; ++iz)
            for (int it = 0; it < n_ring; ++it) {
                const double th = 2.0 * test::kPi * (it + 0.5 * (iz % 2)) / n_ring;
                world.add_sphere(Vec3(rc * std::cos(th), rc * std::sin(th), a + 2.0 * a * iz), a, 2650.0);
            }
        axis_sphere = world.add_sphere(Vec3(0, 0, a * n_rows), a, 2650.0);
    }
    double height() const { return 2.0 * a * n_rows; }
    int count() const { return n_ring * n_rows + 1; }
};
}  // namespace

TEST_CASE("grain pressure: the radial force is p times the envelope's area, on the surface grains, inwards",
          "[engine][grain_pressure]") {
    Rings rings(8);
    boundary::GrainPressure gp(0, rings.count(), rings.R, rings.height(), rings.a);
    const double p = 100e3;
    const double total = gp.apply_pressure(rings.world, p, 0.0, rings.height());
    // The envelope dips between the ring's spheres by less than a few % of R.
    const double lateral = 2.0 * test::kPi * rings.R * rings.height();
    CHECK(total == Approx(p * lateral).epsilon(0.05));
    CHECK(total < p * lateral * (1.0 + 1e-12));
    const auto& f = rings.world.particles().external_force;
    const auto& x = rings.world.particles().position;
    Vec3 resultant = Vec3::Zero();
    double radial_sum = 0.0;
    for (int q = 0; q < rings.count(); ++q) {
        resultant += f[q];
        const Vec3 out(x[q].x(), x[q].y(), 0.0);
        if (q == rings.axis_sphere) continue;
        CHECK(f[q].z() == 0.0);
        CHECK(f[q].dot(out) < 0.0);  // every ring sphere is at the surface and pushed in
        radial_sum -= f[q].dot(out.normalized());
    }
    CHECK(f[rings.axis_sphere].norm() == 0.0);  // shielded
    // Symmetric rings: the pushes cancel; their radial parts add up to the total.
    CHECK(resultant.norm() < 1e-6 * total);
    CHECK(radial_sum == Approx(total).epsilon(0.02));
}

TEST_CASE("grain pressure: a grain that sticks out takes its cells' share, continuously", "[engine][grain_pressure]") {
    Rings rings(6);
    boundary::GrainPressure gp(0, rings.count(), rings.R, rings.height(), rings.a);
    const double p = 50e3;
    const int q = 2 * rings.n_ring + 3;  // a sphere in the third row
    gp.apply_pressure(rings.world, p, 0.0, rings.height());
    const double before = rings.world.particles().external_force[q].norm();
    const Vec3 out = Vec3(rings.world.particles().position[q].x(), rings.world.particles().position[q].y(), 0.0).normalized();
    // Moved out by a fifth of its radius, beyond the neighbours' reach in the cells it covers.
    rings.world.particles().position[q] += 0.2 * rings.a * out;
    const double total = gp.apply_pressure(rings.world, p, 0.0, rings.height());
    const double after = rings.world.particles().external_force[q].norm();
    CHECK(after > 1.25 * before);  // it takes whole cells it shared with its neighbours
    CHECK(total > 0.0);
    // A move far smaller than the sharing depth changes the force by little: no jump.
    rings.world.particles().position[q] -= 0.2 * rings.a * out;
    gp.apply_pressure(rings.world, p, 0.0, rings.height());
    rings.world.particles().position[q] += 1e-4 * rings.a * out;
    gp.apply_pressure(rings.world, p, 0.0, rings.height());
    CHECK(rings.world.particles().external_force[q].norm() == Approx(before).epsilon(0.05));
}

TEST_CASE("grain pressure: the enclosed volume is the envelope's", "[engine][grain_pressure]") {
    Rings rings(10);
    const boundary::GrainPressure gp(0, rings.count(), rings.R, rings.height(), rings.a);
    const double v = gp.enclosed_volume(rings.world, 0.0, rings.height());
    const double cylinder = test::kPi * rings.R * rings.R * rings.height();
    CHECK(v <= cylinder * (1.0 + 1e-12));
    CHECK(v == Approx(cylinder).epsilon(0.06));
    CHECK(gp.mean_radius(rings.world, 0.0, rings.height()) == Approx(rings.R).epsilon(0.03));
    // The rings pushed out by 1 mm: the volume follows.
    auto& x = rings.world.particles().position;
    for (int q = 0; q < rings.count(); ++q) {
        if (q == rings.axis_sphere) continue;
        const Vec3 out = Vec3(x[q].x(), x[q].y(), 0.0).normalized();
        x[q] += 1e-3 * out;
    }
    const double v2 = gp.enclosed_volume(rings.world, 0.0, rings.height());
    CHECK(v2 / v == Approx(std::pow((rings.R + 1e-3) / rings.R, 2)).epsilon(0.01));
}

TEST_CASE("grain pressure: skipping the interior grains gives the forces of a visit of every grain",
          "[engine][grain_pressure]") {
    Rings rings(8);
    // Interior spheres between the axis and the rings, away from the axis sphere.
    for (int k = 0; k < 6; ++k) {
        const double th = 2.0 * test::kPi * k / 6.0;
        rings.world.add_sphere(Vec3(0.012 * std::cos(th), 0.012 * std::sin(th), 0.004 + 0.005 * k), rings.a, 2650.0);
    }
    const int count = static_cast<int>(rings.world.particles().position.size());
    const int interior = rings.count();  // the first interior sphere, at angle 0 and z = 4 mm
    const double p = 80e3;
    auto forces_of_a_fresh_boundary = [&](double* total) {
        boundary::GrainPressure fresh(0, count, rings.R, rings.height(), rings.a);  // visits every grain
        *total = fresh.apply_pressure(rings.world, p, 0.0, rings.height());
        return rings.world.particles().external_force;
    };
    boundary::GrainPressure reused(0, count, rings.R, rings.height(), rings.a);
    reused.apply_pressure(rings.world, p, 0.0, rings.height());  // sets the interior bound
    auto& x = rings.world.particles().position;
    const auto& f = rings.world.particles().external_force;
    for (int step = 0; step < 2; ++step) {
        // Step 0: the grains stay; step 1: the ring sphere in front of the first interior one
        // (bottom row, angle 0) moves to the axis, so the envelope there drops below the bound
        // of the previous call, the interior sphere becomes the outermost in those cells, and
        // every grain must be visited.
        if (step == 1) x[0] = Vec3(0.0, 0.0, x[0].z());
        const double total = reused.apply_pressure(rings.world, p, 0.0, rings.height());
        const auto skipped = f;
        double fresh_total = 0.0;
        const auto all = forces_of_a_fresh_boundary(&fresh_total);
        CHECK(total == fresh_total);
        for (int q = 0; q < count; ++q) CHECK((skipped[q].array() == all[q].array()).all());
        if (step == 0) CHECK(all[interior].norm() == 0.0);
        else CHECK(all[interior].norm() > 0.0);
    }
}
