// Seating and membrane artefacts as post-processing of predicted curves.
#include <catch2/catch.hpp>

#include "engine/diagnose/test_artefacts.hpp"
#include "lab_fixtures.hpp"

using namespace triax::diagnose;
using namespace triax::diagnose::testing;

namespace {
LabDataset dataset() {
    LabDataset d;
    d.curves.push_back(shear_curve(100e3, {0.0, 0.01, 0.02}, {0.0, 1e5, 1.5e5}, {0.0, 0.001, 0.0015}));
    for (int s = 1; s <= 2; ++s)
        d.curves.push_back(creep_curve(s, 100e3, {0.0, 100.0}, {0.001, 0.002}, 0.0, {0.0002, 0.0004}));
    return d;
}
}  // namespace

TEST_CASE("seating shifts the shear curve, adds an unloaded branch and offsets creep stage 1 only", "[diagnose][artefacts]") {
    auto d = dataset();
    apply_test_artefact(d, Effect::SeatingError, {0.005});
    const auto& sh = d.curves[0];
    REQUIRE(sh.axial_strain.size() == 4);
    CHECK(sh.axial_strain[0] == 0.0);
    CHECK(sh.axial_strain[1] == Approx(0.005));
    CHECK(sh.deviator_pa[1] == 0.0);
    CHECK(sh.axial_strain[3] == Approx(0.025));
    CHECK(sh.deviator_pa[3] == Approx(1.5e5));
    CHECK(d.curves[1].axial_strain[0] == Approx(0.006));
    CHECK(d.curves[1].axial_deformation_m[0] == Approx(0.0002 + 0.001));
    CHECK(d.curves[2].axial_strain[0] == Approx(0.001));
}

TEST_CASE("membrane adds K_m * eps_a to the deviator, the same at any confinement", "[diagnose][artefacts]") {
    auto d = dataset();
    apply_test_artefact(d, Effect::MembraneCompliance, {2e5});
    CHECK(d.curves[0].deviator_pa[2] == Approx(1.5e5 + 2e5 * 0.02));
    CHECK(d.curves[1].axial_strain[1] == Approx(0.002));
}

TEST_CASE("physical effects and wrong parameter counts are rejected", "[diagnose][artefacts]") {
    auto d = dataset();
    CHECK_THROWS_WITH(apply_test_artefact(d, Effect::RollingResistance, {0.1}), Catch::Contains("not a test artefact"));
    CHECK_THROWS_WITH(apply_test_artefact(d, Effect::SeatingError, {0.1, 0.2}), Catch::Contains("1 parameter"));
}
