// RunEstimate (steps and minutes before a run) and the membrane's hold on the grains:
// the automatic membrane radius never below the smallest grain, a chosen one refused when
// too fine (the failure of preset B at 150 grains, docs/web.md).
#include "engine/boundary/membrane.hpp"
#include "engine/core/types.hpp"
#include "engine/creep/time_schedule.hpp"
#include "engine/protocol/paper_groups.hpp"
#include "engine/protocol/run_estimate.hpp"

#include <catch2/catch.hpp>

using namespace triax;
using namespace triax::protocol;

TEST_CASE("estimate: steps per phase from the protocol, minutes as a range", "[protocol][estimate]") {
    TestScheme s = paper_group("B");
    const auto e = estimate_run(s);
    CHECK(e.size.grains > 2000);
    // Creep increments: creep_time_increments of each stage.
    long long inc = 0;
    for (double d : s.loading.stage_durations_s)
        inc += static_cast<long long>(creep::creep_time_increments(d, s.creep.first_increment_s, s.creep.increment_growth,
                                                                   s.creep.max_increment_s)
                                          .size());
    CHECK(e.creep_increments == inc);
    CHECK(e.creep.low == 4 * kLoadingHoldMin + inc * kIncrementHoldMin);
    CHECK(e.creep.high == 4 * kLoadingHoldMax + inc * kIncrementHoldMax);
    CHECK(e.total.low < e.total.typical);
    CHECK(e.total.typical < e.total.high);
    CHECK(e.minutes_low < e.minutes_typical);
    CHECK(e.minutes_typical < e.minutes_high);
    // The shear at the quasi-static rate: twice the strain, twice the steps.
    TestScheme longer = s;
    longer.loading.max_axial_strain *= 2.0;
    CHECK(static_cast<double>(estimate_run(longer).shear.typical) == Approx(2.0 * e.shear.typical).epsilon(1e-6));
    // No creep stage: no creep steps.
    TestScheme shear_only = s;
    shear_only.loading.stress_levels.clear();
    shear_only.loading.stage_durations_s.clear();
    CHECK(estimate_run(shear_only).creep.typical == 0);
}

TEST_CASE("estimate: the automatic membrane holds the smallest grain (ratio at most 1.2)", "[protocol][estimate]") {
    // Fine grains: a quarter of the mean radius, at least 1 mm, at most D/20.
    CHECK(boundary::automatic_membrane_radius(0.5e-3, 1.0e-3, 0.1) == Approx(1.0e-3));
    CHECK(boundary::automatic_membrane_radius(2.879e-3, 4.3e-3, 0.1) == Approx(2.879e-3));
    // Grains scaled up beyond D/20: the smallest grain over 1.2, not the cap.
    CHECK(boundary::automatic_membrane_radius(7.7e-3, 11.5e-3, 0.1) == Approx(7.7e-3 / 1.2));
    // Just above the cap (the protocol's reduced specimens): the cap still holds them.
    CHECK(boundary::automatic_membrane_radius(2.52e-3, 5.0e-3, 0.05) == Approx(2.5e-3));
    TestScheme s = paper_group("B");
    s.max_particles = 150;
    const auto e = estimate_run(s);
    CHECK(e.membrane_radius_m * boundary::kAutomaticGrainToMembraneRadius >= 7.0e-3);
    CHECK(e.size.grains <= 160);
    CHECK_FALSE(e.warnings.empty());  // 3 largest grains across the specimen
}

TEST_CASE("validate refuses a membrane too fine for the grains, naming the size to set", "[protocol][estimate]") {
    TestScheme s = paper_group("B");
    s.max_particles = 150;
    s.micro.membrane_particle_radius_m = 5.0e-3;  // smallest grain ~7.7 mm: ratio 1.54, lost a grain
    try {
        s.validate();
        FAIL("a 5 mm membrane for 7.7 mm grains was accepted");
    } catch (const InputError& err) {
        const std::string why = err.what();
        CHECK(why.rfind("micro.membrane_particle_radius_m:", 0) == 0);
        CHECK(why.find("at least") != std::string::npos);
        CHECK(why.find("max_particles") != std::string::npos);
    }
    s.micro.membrane_particle_radius_m = 6.0e-3;  // ratio 1.28: consolidated (measured)
    CHECK_NOTHROW(s.validate());
    s.micro.membrane_particle_radius_m = 0.0;     // automatic
    CHECK_NOTHROW(s.validate());
}
