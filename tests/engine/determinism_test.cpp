// Invariants of the loop: 1 and 2 threads agree bitwise, particle order does not
// matter, Newton's third law holds for every step's force set, inactive slots hold zeros.
#include "engine/core/world.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <numeric>
#include <string>

using namespace triax;

namespace {

constexpr int kSide = 17;          // 4913 spheres: above the parallel threshold
constexpr double kRmin = 1.2e-3, kRmax = 1.5e-3;

World make_world(const std::vector<test::SphereSpec>& spheres, const std::vector<int>& order, int threads) {
    World w;
    w.set_threads(threads);
    w.set_default_contact_law(test::linear_law(1e3, 5e2, 0.4));
    const double L = kSide * 2.05 * kRmax;
    test::add_box(w, L);
    for (int k : order) w.add_sphere(spheres[k].x, spheres[k].r, 2650.0);
    // Shake the assembly: random-ish initial velocities, derived from the sphere not its index.
    for (std::size_t p = 0; p < order.size(); ++p) {
        const Vec3& x = spheres[order[p]].x;
        w.particles().velocity[p] = 0.5 * Vec3(std::sin(1e4 * x.y()), std::cos(1e4 * x.z()), std::sin(1e4 * x.x()));
    }
    w.set_gravity(Vec3(0, 0, -200.0));  // strong, so a dense pile forms in few steps
    w.set_time_step(w.critical_time_step(0.2));
    return w;
}

// The lattice world of `seed`, spheres added in their own order, on `threads` threads.
World lattice_world(int seed, int threads) {
    const auto spheres = test::lattice_spheres(kSide, kRmin, kRmax, seed);
    std::vector<int> order(spheres.size());
    std::iota(order.begin(), order.end(), 0);
    return make_world(spheres, order, threads);
}

// The same lattice world built twice, on 1 and on 2 threads (the parallel cases' set-up).
struct OneAndTwoThreads {
    World one, two;
    std::size_t n = 0;
};
OneAndTwoThreads one_and_two_threads() {
    const auto spheres = test::lattice_spheres(kSide, kRmin, kRmax, 7);
    std::vector<int> order(spheres.size());
    std::iota(order.begin(), order.end(), 0);
    return {make_world(spheres, order, 1), make_world(spheres, order, 2), spheres.size()};
}

// Particles whose position, velocity or spin differ in any bit (each field counts once).
long differing_particles(const World& a, const World& b, std::size_t n) {
    long differing = 0;
    for (std::size_t p = 0; p < n; ++p) {
        differing += a.particles().position[p] != b.particles().position[p];
        differing += a.particles().velocity[p] != b.particles().velocity[p];
        differing += a.particles().angular_velocity[p] != b.particles().angular_velocity[p];
    }
    return differing;
}

}  // namespace

TEST_CASE("1 and 2 threads give bitwise identical trajectories", "[engine][parallel]") {
    auto [one, two, n] = one_and_two_threads();
    one.cycle(1500);
    two.cycle(1500);
    REQUIRE(one.active_contact_count() > 1000);
    REQUIRE(one.contacts().size() >= 4096);  // the contact loop really ran in parallel
    CHECK(differing_particles(one, two, n) == 0);
    CHECK(one.energy().slip == two.energy().slip);
    CHECK(one.energy().damping == two.energy().damping);
}

// The 2-thread step runs a run of steps in one thread team and leaves it for every
// neighbour rebuild and at the end of each cycle() call: many short calls (as the
// protocol's servo chunks make) must give the same trajectory as one long call.
TEST_CASE("2 threads in short cycle() calls equal 1 thread in one call", "[engine][parallel]") {
    auto [one, two, n] = one_and_two_threads();
    one.cycle(600);
    for (int k = 0; k < 60; ++k) two.cycle(k % 2 ? 7 : 13);
    REQUIRE(two.step() == 600);
    REQUIRE(one.neighbor_rebuild_count() > 2);
    CHECK(one.neighbor_rebuild_count() == two.neighbor_rebuild_count());
    CHECK(differing_particles(one, two, n) == 0);
    CHECK(one.energy().kinetic == two.energy().kinetic);
    CHECK(one.energy().slip == two.energy().slip);
}

TEST_CASE("an instability inside the 2-thread team is thrown with its step", "[engine][parallel][errors]") {
    const auto spheres = test::lattice_spheres(kSide, kRmin, kRmax, 7);
    std::vector<int> order(spheres.size());
    std::iota(order.begin(), order.end(), 0);
    World two = make_world(spheres, order, 2);
    two.cycle(20);
    // A particle that jumps more than its radius per step: "exploding kinetic energy".
    two.particles().velocity[100] = Vec3(0, 0, 1e6);
    try {
        two.cycle(50);
        FAIL("no SimulationError");
    } catch (const SimulationError& e) {
        CHECK(e.step() == 20);
        CHECK(std::string(e.what()).find("particle 100") != std::string::npos);
    }
    // The world stays usable: the step counter did not advance past the failed step.
    CHECK(two.step() == 20);
}

// Reordering changes the order of floating-point sums (gather lists follow indices), so
// trajectories agree to round-off, not bitwise; in a collisional flow round-off grows
// exponentially, so the comparison is kept to a few hundred steps (measured: ~1e-11).
TEST_CASE("reordering the particles changes nothing", "[engine][invariant]") {
    const auto spheres = test::lattice_spheres(kSide, kRmin, kRmax, 11);
    std::vector<int> order(spheres.size());
    std::iota(order.begin(), order.end(), 0);
    std::vector<int> shuffled = order;
    test::Rng rng(3);
    for (std::size_t k = shuffled.size() - 1; k > 0; --k)
        std::swap(shuffled[k], shuffled[static_cast<std::size_t>(rng.uniform() * (k + 1))]);
    World a = make_world(spheres, order, 1);
    World b = make_world(spheres, shuffled, 2);
    a.cycle(400);
    b.cycle(400);
    REQUIRE(a.active_contact_count() > 300);
    CHECK(a.active_contact_count() == b.active_contact_count());
    double worst = 0.0;
    for (std::size_t p = 0; p < shuffled.size(); ++p) {
        const int k = shuffled[p];
        const Vec3 da = a.particles().position[k] - spheres[k].x;
        const Vec3 db = b.particles().position[p] - spheres[k].x;
        worst = std::max(worst, (da - db).norm() / std::max(da.norm(), 1e-9));
    }
    CHECK(worst <= 1e-9);
    CHECK(a.energy().slip == Approx(b.energy().slip).epsilon(1e-9));
}

TEST_CASE("Newton's third law: contact forces sum to minus the wall forces", "[engine][invariant]") {
    World w = lattice_world(5, 2);
    for (int round = 0; round < 5; ++round) {
        w.cycle(100);
        Vec3 net = Vec3::Zero();
        double scale = 0.0;
        const auto& pa = w.particles();
        for (std::size_t p = 0; p < pa.size(); ++p) {
            const Vec3 contact = pa.force[p] - pa.mass[p] * w.gravity() - pa.external_force[p];
            net += contact;
            scale += contact.norm();
        }
        for (std::size_t k = 0; k < w.plane_wall_count(); ++k) net += w.plane_wall(static_cast<int>(k)).force;
        REQUIRE(scale > 0);
        CHECK(net.norm() <= 1e-12 * scale);
        // Each contact exerts no net moment about its own contact point: the torque pair
        // balances the force pair (positions at force time: x - v dt).
        const auto& c = w.contacts();
        long bad = 0;
        for (std::size_t k = 0; k < c.size(); ++k) {
            if (!c.active[k] || c.rolling_moment[k].norm() > 0) continue;
            const int i = c.i[k], j = c.j[k];
            const Vec3 xi = pa.position[i] - pa.velocity[i] * w.time_step();
            const Vec3 xj = pa.position[j] - pa.velocity[j] * w.time_step();
            const Vec3 moment = c.torque_on_i[k] + c.torque_on_j[k] + (xi - c.contact_point[k]).cross(-c.force_on_j[k]) +
                                (xj - c.contact_point[k]).cross(c.force_on_j[k]);
            bad += moment.norm() > 1e-12 * c.force_on_j[k].norm();
        }
        CHECK(bad == 0);
    }
}

TEST_CASE("inactive contact slots hold zero force and torques (the gather adds every slot)", "[engine][invariant]") {
    // The gather adds every candidate slot of a particle, so a slot that is not active
    // (never touched, or opened since) must hold exact zeros (contact_store.hpp).
    World w = lattice_world(5, 2);
    for (int round = 0; round < 5; ++round) {
        w.cycle(100);
        const auto& c = w.contacts();
        long inactive = 0, loaded = 0;
        for (std::size_t k = 0; k < c.size(); ++k) {
            if (c.active[k]) continue;
            ++inactive;
            loaded += c.force_on_j[k] != Vec3::Zero() || c.torque_on_i[k] != Vec3::Zero() ||
                      c.torque_on_j[k] != Vec3::Zero();
        }
        CHECK(inactive > 0);
        CHECK(loaded == 0);
    }
}
