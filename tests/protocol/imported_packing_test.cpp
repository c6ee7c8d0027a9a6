// The specimen an imported packing makes (packing_extent): the platens where the packing
// names them or against its outermost grains, a fresh membrane at the grains' envelope.
#include <catch2/catch.hpp>

#include <cmath>

#include "engine/protocol/imported_packing.hpp"
#include "engine/protocol/specimen.hpp"

using namespace triax;
using namespace triax::protocol;

namespace {

// 40 x 80 mm, 4 mm membrane spheres.
TestScheme scheme_40_by_80() {
    TestScheme s;
    s.specimen.diameter_m = 0.04;
    s.specimen.height_m = 0.08;
    s.gradation.r_min_m = 2.0e-3;
    s.gradation.radius_ratio = 2.0;
    s.micro.membrane_particle_radius_m = 4.0e-3;
    return s;
}

// Grains of 3 mm on the axis from z_lo to z_hi and one out at radius `reach` - 3 mm.
ImportedPacking column(double z_lo, double z_hi, double reach) {
    ImportedPacking p;
    const double r = 3e-3;
    for (double z = z_lo + r; z <= z_hi - r + 1e-12; z += 2.0 * r) p.position.push_back(Vec3(0, 0, z));
    p.position.back().z() = z_hi - r;
    p.position.push_back(Vec3(reach - r, 0, 0.5 * (z_lo + z_hi)));
    p.radius.assign(p.position.size(), r);
    return p;
}

}  // namespace

TEST_CASE("an imported packing's platens are its own", "[protocol][packing]") {
    SECTION("against the outermost grains when the packing names none") {
        const auto e = packing_extent(column(-0.0404, 0.0392, 0.02));
        CHECK(e.bottom_z_m == Approx(-0.0404));
        CHECK(e.top_z_m == Approx(0.0392));
        CHECK(e.centre_z_m() == Approx(-0.0006));
    }
    SECTION("where the packing names them") {
        ImportedPacking p = column(-0.0404, 0.0392, 0.02);
        p.platen_z_m = {-0.0401, 0.0393};
        const auto e = packing_extent(p);
        CHECK(e.bottom_z_m == -0.0401);
        CHECK(e.top_z_m == 0.0393);
    }
}

TEST_CASE("an imported packing's fresh membrane wraps its grains", "[protocol][packing]") {
    // Shrunk, bulged, or reaching past D/2 = 20 mm into the gaps of the old lattice: the
    // grains' envelope, so that no grain starts inside a sphere of the new one.
    CHECK(packing_extent(column(-0.04, 0.04, 0.0170)).radius_m == Approx(0.017));
    CHECK(packing_extent(column(-0.04, 0.04, 0.025)).radius_m == Approx(0.025));
    CHECK(packing_extent(column(-0.04, 0.04, 0.0215)).radius_m == Approx(0.0215));
}

TEST_CASE("a specimen from a shortened, bulged packing is built around it", "[protocol][packing]") {
    TestScheme s = scheme_40_by_80();
    const ImportedPacking p = column(-0.036, 0.032, 0.025);
    s.packing = std::make_shared<ImportedPacking>(p);
    Specimen sp(s);
    CHECK(sp.bottom_z() == Approx(-0.036));
    CHECK(sp.top_z() == Approx(0.032));
    REQUIRE(sp.membrane() != nullptr);
    const auto& m = *sp.membrane();
    CHECK(m.mean_inner_radius(sp.world()) == Approx(0.025).epsilon(1e-6));
    // The membrane's rows span the platens: none above the top or below the bottom.
    const auto& x = sp.world().particles().position;
    double lo = 1.0, hi = -1.0;
    for (int k = m.first_index(); k < m.first_index() + m.count(); ++k) {
        lo = std::min(lo, x[k].z() - m.particle_radius());
        hi = std::max(hi, x[k].z() + m.particle_radius());
    }
    CHECK(lo == Approx(-0.036));
    CHECK(hi == Approx(0.032));
}
