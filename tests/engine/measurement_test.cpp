// MeasurementSphere against closed forms on a simple cubic lattice.
#include "engine/core/world.hpp"
#include "engine/measure/measurement_sphere.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>

using namespace triax;
using triax::test::kPi;

TEST_CASE("sphere-sphere intersection volume", "[engine][measure]") {
    const double R = 2.0;
    CHECK(MeasurementSphere::intersection_volume(R, 0.5, 0.0) == Approx(4.0 / 3.0 * kPi * 0.125));
    CHECK(MeasurementSphere::intersection_volume(R, 0.5, 1.4) == Approx(4.0 / 3.0 * kPi * 0.125));
    CHECK(MeasurementSphere::intersection_volume(R, 0.5, 2.6) == 0.0);
    // Equal spheres at distance R: lens of volume 5 pi R^3 / 12.
    CHECK(MeasurementSphere::intersection_volume(R, R, R) == Approx(5.0 * kPi * R * R * R / 12.0));
    // Symmetric in the two radii.
    CHECK(MeasurementSphere::intersection_volume(1.0, 0.4, 1.1) == Approx(MeasurementSphere::intersection_volume(0.4, 1.0, 1.1)));
}

TEST_CASE("porosity, coordination and stress of a compressed simple cubic lattice", "[engine][measure]") {
    World w;
    const double r = 1e-3, overlap = 2e-6, kn = 1e5;
    const double a = 2 * r - overlap;  // lattice spacing
    const int n = 16;
    w.set_default_contact_law(test::linear_law(kn, kn, 0.5));
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) w.add_sphere(Vec3(x * a, y * a, z * a), r, 2650.0);
    w.set_time_step(1e-9);
    w.set_local_damping(0.0);
    w.cycle(1);
    const Vec3 centre = Vec3::Constant(7.5 * a);
    MeasurementSphere ms(centre, 5 * a);
    const MeasurementReading m = ms.measure(w);
    CHECK(m.porosity == Approx(1.0 - kPi / 6.0 * std::pow(2 * r / a, 3)).epsilon(0.01));
    CHECK(m.coordination == Approx(6.0));
    const double sigma = kn * overlap / (a * a);  // force per contact over the area per contact
    CHECK(m.stress(0, 0) == Approx(sigma).epsilon(0.02));
    CHECK(m.stress(1, 1) == Approx(sigma).epsilon(0.02));
    CHECK(m.stress(2, 2) == Approx(sigma).epsilon(0.02));
    CHECK(std::abs(m.stress(0, 1)) < 1e-6 * sigma);
    CHECK(m.stress(0, 0) > 0);  // compression positive
}

TEST_CASE("mean displacement since reference and mean spin", "[engine][measure]") {
    World w;
    for (int k = 0; k < 10; ++k) w.add_sphere(Vec3(0.01 * k, 0, 0), 1e-3, 2650.0);
    MeasurementSphere ms(Vec3(0.045, 0, 0), 0.03);
    ms.set_reference(w);
    for (std::size_t p = 0; p < w.particle_count(); ++p) {
        w.particles().velocity[p] = Vec3(0, 0, -0.1);
        w.particles().angular_velocity[p] = Vec3(0, 2.0, -1.0);
    }
    w.set_local_damping(0.0);
    w.set_time_step(1e-4);
    w.cycle(100);
    const MeasurementReading m = ms.measure(w);
    CHECK(m.mean_displacement.z() == Approx(-0.1 * 100 * 1e-4));
    CHECK(m.mean_displacement.x() == Approx(0.0).margin(1e-12));
    CHECK(m.mean_angular_velocity.y() == Approx(2.0));
    CHECK(m.mean_angular_velocity.z() == Approx(-1.0));
    CHECK(m.particle_count == 6);
}
