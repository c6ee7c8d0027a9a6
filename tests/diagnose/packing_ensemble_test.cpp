// The mean over packings (packing_ensemble.hpp): curves matched by kind, pressure and stage,
// read along the first packing's abscissa, cut where the shortest ends; a curve only some
// packings have is the mean of those.
#include "engine/diagnose/packing_ensemble.hpp"

#include <catch2/catch.hpp>

using namespace triax::diagnose;

namespace {

LabCurve shear(double s3, std::vector<double> eps, double q_slope, double ev_slope) {
    LabCurve c;
    c.kind = CurveKind::Shear;
    c.confining_pa = s3;
    c.axial_strain = std::move(eps);
    for (double e : c.axial_strain) {
        c.deviator_pa.push_back(q_slope * e);
        c.volumetric_strain.push_back(ev_slope * e);
    }
    return c;
}

LabCurve creep(double s3, int stage, std::vector<double> t, double rate) {
    LabCurve c;
    c.kind = CurveKind::Creep;
    c.confining_pa = s3;
    c.stage = stage;
    c.time_s = std::move(t);
    for (double x : c.time_s) {
        c.axial_strain.push_back(rate * x);
        c.axial_deformation_m.push_back(0.1 * rate * x);
    }
    return c;
}

}  // namespace

TEST_CASE("the mean over packings averages matched curves along the first packing's abscissa", "[diagnose][ensemble]") {
    LabDataset a, b;
    a.curves = {shear(100e3, {0.0, 0.01, 0.02, 0.03}, 1e7, 0.1), creep(100e3, 1, {0, 60, 120}, 1e-6),
                creep(100e3, 2, {0, 60, 120}, 2e-6)};
    // Packing b: other readings, a shorter shear, a q twice as steep, and a rupture in stage 1
    // (no stage 2).
    b.curves = {shear(100e3, {0.0, 0.015, 0.025}, 2e7, 0.3), creep(100e3, 1, {0, 30, 90, 150}, 3e-6)};
    const LabDataset m = mean_over_packings({a, b});
    REQUIRE(m.curves.size() == 3);

    const LabCurve& s = m.curves[0];
    REQUIRE(s.kind == CurveKind::Shear);
    // a's strains, cut at b's last (2.5 %): 0, 1, 2 %.
    REQUIRE(s.axial_strain == std::vector<double>{0.0, 0.01, 0.02});
    for (std::size_t i = 0; i < 3; ++i) {
        CHECK(s.deviator_pa[i] == Approx(1.5e7 * s.axial_strain[i]).margin(1e-6));
        CHECK(s.volumetric_strain[i] == Approx(0.2 * s.axial_strain[i]).margin(1e-12));
    }
    CHECK(s.axial_deformation_m.empty());

    const LabCurve& c1 = m.curves[1];
    REQUIRE(c1.stage == 1);
    REQUIRE(c1.time_s == std::vector<double>{0, 60, 120});
    CHECK(c1.axial_strain[2] == Approx(2e-6 * 120));
    CHECK(c1.axial_deformation_m[1] == Approx(0.1 * 2e-6 * 60));

    // Stage 2 only in a: a's curve.
    const LabCurve& c2 = m.curves[2];
    REQUIRE(c2.stage == 2);
    CHECK(c2.axial_strain == a.curves[2].axial_strain);
}

TEST_CASE("one packing is returned as it is", "[diagnose][ensemble]") {
    LabDataset a;
    a.curves = {shear(50e3, {0.0, 0.01}, 1e7, 0.1)};
    const LabDataset m = mean_over_packings({a});
    REQUIRE(m.curves.size() == 1);
    CHECK(m.curves[0].deviator_pa == a.curves[0].deviator_pa);
    CHECK(mean_over_packings({}).curves.empty());
}
