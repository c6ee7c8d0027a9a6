// SpecimenBudget: the estimate against what the builder really draws, and the hard limits
// TestScheme::validate applies whatever max_particles says.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "engine/boundary/membrane.hpp"
#include "engine/core/types.hpp"
#include "engine/core/world.hpp"
#include "engine/protocol/gradation.hpp"
#include "engine/protocol/paper_groups.hpp"
#include "engine/protocol/specimen_budget.hpp"

using namespace triax;
using protocol::GradationSpec;
using protocol::TestScheme;

namespace {
constexpr double kPi = 3.14159265358979323846;

double solid_volume(const TestScheme& s) {
    const double r = 0.5 * s.specimen.diameter_m;
    return (1.0 - s.specimen.target_porosity) * kPi * r * r * s.specimen.height_m;
}

// Mean drawn count over a few seeds, as specimen.cpp draws them (with its max_particles scaling).
double drawn_count(const TestScheme& s, int seeds = 4) {
    double total = 0.0;
    for (int seed = 1; seed <= seeds; ++seed) {
        std::mt19937_64 rng(seed);
        GradationSpec g = s.gradation;
        auto radii = protocol::draw_radii(g, solid_volume(s), rng);
        if (s.max_particles > 0 && static_cast<int>(radii.size()) > s.max_particles) {
            const double f = std::cbrt(static_cast<double>(radii.size()) / s.max_particles) * 1.02;
            g.r_min_m *= f;
            for (auto& p : g.sieve_curve) p.size_m *= f;
            g.fines_cutoff_m *= f;
            rng.seed(seed);
            radii = protocol::draw_radii(g, solid_volume(s), rng);
        }
        total += static_cast<double>(radii.size());
    }
    return total / seeds;
}

std::string refusal(const TestScheme& s) {
    try {
        s.validate();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST_CASE("budget: the grain estimate matches the radius-ratio draw", "[protocol][budget]") {
    TestScheme s;
    s.gradation.r_min_m = 1.0e-3;
    s.gradation.radius_ratio = 3.0;
    const auto b = protocol::estimate_specimen_size(s);
    const double drawn = drawn_count(s);
    CHECK(drawn > 1000.0);
    CHECK(static_cast<double>(b.grains) == Approx(drawn).epsilon(0.05));
    CHECK(b.contacts_estimate >= 3 * b.grains);
    CHECK(b.memory_bytes > 256.0 * static_cast<double>(b.grains));
}

TEST_CASE("budget: the grain estimate matches the sieve-curve draw with lumped fines", "[protocol][budget]") {
    TestScheme s;
    s.gradation.kind = GradationSpec::Kind::SieveCurve;
    s.gradation.fines_cutoff_m = 1.0e-3;
    s.gradation.sieve_curve = {{0.5e-3, 0.0}, {1e-3, 5.0}, {2e-3, 30.0}, {5e-3, 70.0}, {10e-3, 100.0}};
    const double drawn = drawn_count(s);
    CHECK(drawn > 1000.0);
    CHECK(static_cast<double>(protocol::estimate_specimen_size(s).grains) == Approx(drawn).epsilon(0.05));
}

TEST_CASE("budget: max_particles scales the estimate as the builder scales the grains", "[protocol][budget]") {
    TestScheme s;
    s.gradation.r_min_m = 0.5e-3;
    s.gradation.radius_ratio = 2.0;
    s.max_particles = 3000;
    const auto b = protocol::estimate_specimen_size(s);
    CHECK(b.grains <= s.max_particles);
    CHECK(static_cast<double>(b.grains) == Approx(drawn_count(s)).epsilon(0.05));
    CHECK(protocol::estimate_drawn_grains(s) > 100000.0);
}

TEST_CASE("budget: the membrane count is the Membrane lattice's", "[protocol][budget]") {
    TestScheme s;
    s.micro.membrane_particle_radius_m = 2.0e-3;
    World w;
    const boundary::Membrane m(w, 0.5 * s.specimen.diameter_m, s.specimen.height_m, 2.0e-3, 1000.0, 1);
    CHECK(protocol::estimate_specimen_size(s).membrane_particles == m.count());
    // Automatic radius: 1 mm floor for the paper's fine grains.
    s.micro.membrane_particle_radius_m = 0.0;
    s.gradation.r_min_m = 0.2e-3;
    s.gradation.radius_ratio = 2.0;
    s.max_particles = 2000;
    const auto b = protocol::estimate_specimen_size(s);
    World w2;
    const double f = std::cbrt(protocol::estimate_drawn_grains(s) / s.max_particles) * 1.02;
    const double r_mean = 0.5 * (0.2e-3 + 0.4e-3) * f;
    const double rm = std::clamp(std::max(0.2e-3 * f, 0.25 * r_mean), 1.0e-3, 0.05 * s.specimen.diameter_m);
    const boundary::Membrane m2(w2, 0.5 * s.specimen.diameter_m, s.specimen.height_m, rm, 1000.0, 1);
    CHECK(b.membrane_particles == m2.count());
}

TEST_CASE("budget: validate refuses a hostile gradation whatever max_particles says", "[protocol][budget]") {
    TestScheme s;
    s.gradation.r_min_m = 1.0e-9;
    s.max_particles = 2000;
    const std::string why = refusal(s);
    CHECK(why.rfind("gradation.r_min_m:", 0) == 0);
    CHECK(why.find("whatever max_particles says") != std::string::npos);
    // The uncapped draw is the hazard: a finite but huge estimate, not an overflow.
    CHECK(protocol::estimate_drawn_grains(s) > 1.0e18);
    CHECK(protocol::estimate_specimen_size(s).grains <= s.max_particles);

    TestScheme sieve;
    sieve.gradation.kind = GradationSpec::Kind::SieveCurve;
    sieve.gradation.sieve_curve = {{1e-8, 0.0}, {1e-3, 100.0}};
    sieve.gradation.fines_cutoff_m = 1e-9;
    CHECK(refusal(sieve).rfind("gradation.sieve_curve[0]:", 0) == 0);
}

TEST_CASE("budget: validate refuses a membrane or specimen over the particle budget", "[protocol][budget]") {
    TestScheme s;
    s.micro.membrane_particle_radius_m = 1.0e-5;  // a 10 um lattice: ~1e8 spheres
    CHECK(refusal(s).rfind("micro.membrane_particle_radius_m:", 0) == 0);

    TestScheme big;  // 3 mm grains in a 1 m x 2 m specimen: 4.4e6 grains asked, cap above the budget
    big.specimen.diameter_m = 1.0;
    big.specimen.height_m = 2.0;
    big.gradation.r_min_m = 3.0e-3;
    big.gradation.radius_ratio = 1.5;
    big.max_particles = 5000000;
    CHECK(refusal(big).rfind("max_particles:", 0) == 0);
    big.max_particles = 100000;  // capped: accepted
    CHECK(refusal(big).empty());
}

TEST_CASE("budget: the paper groups and the default scheme are within the budget", "[protocol][budget]") {
    CHECK(refusal(TestScheme{}).empty());
    for (const auto& g : protocol::paper_groups()) {
        INFO(g.name);
        CHECK(refusal(g.scheme).empty());
        const auto b = protocol::estimate_specimen_size(g.scheme);
        CHECK(b.grains > 0);
        CHECK(b.memory_bytes < protocol::kMaxSpecimenMemoryBytes);
    }
}
