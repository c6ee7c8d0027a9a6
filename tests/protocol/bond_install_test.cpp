// Soil bonds formed on the consolidated fabric: strength per contact from the cement's
// strength over the pair's smaller cross-section, plus (micro.bond_load_ratio) a multiple of
// the normal force the contact carried when the bond formed.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "engine/creep/moisture_bond.hpp"
#include "engine/protocol/specimen.hpp"
#include "tests/support/reduced_specimen.hpp"

using namespace triax;
using namespace triax::protocol;

TEST_CASE("a bond cemented under load gains the ratio times its contact's normal force", "[protocol][bond]") {
    TestScheme s = testing::reduced_scheme(4.0e-3, 0.05, 3);
    s.micro.bond_normal_strength_pa = 300.0e3;
    s.micro.bond_shear_strength_pa = 200.0e3;
    s.specimen.moisture_content = 0.102;  // the moisture relation scales the whole strength
    const double factor = creep::bond_strength_factor(0.102);
    REQUIRE(factor < 1.0);

    Specimen plain(s);
    s.micro.bond_load_ratio = 2.5;
    Specimen loaded(s);  // the same seed: the same fabric and forces
    REQUIRE(plain.install_soil_bonds() == loaded.install_soil_bonds());

    const auto& a = plain.world().contacts();
    const auto& b = loaded.world().contacts();
    const auto& r = plain.world().particles().radius;
    REQUIRE(a.i.size() == b.i.size());
    int bonded = 0, pressed = 0;
    for (std::size_t k = 0; k < a.i.size(); ++k) {
        if (!a.bonded[k] || plain.world().particles().group[a.i[k]] != kSoilGroup ||
            plain.world().particles().group[a.j[k]] != kSoilGroup)
            continue;
        ++bonded;
        const double area = 3.141592653589793 * std::pow(std::min(r[a.i[k]], r[a.j[k]]), 2);
        CHECK(a.bond_normal_strength[k] == Approx(factor * 300.0e3 * area));
        CHECK(a.bond_shear_strength[k] == Approx(factor * 200.0e3 * area));
        const double fn = std::max(a.normal_force[k], 0.0);
        pressed += fn > 0.0 ? 1 : 0;
        CHECK(b.bond_normal_strength[k] == Approx(a.bond_normal_strength[k] + factor * 2.5 * fn));
        CHECK(b.bond_shear_strength[k] == Approx(a.bond_shear_strength[k] + factor * 2.5 * fn));
    }
    CHECK(bonded > 50);
    CHECK(pressed > bonded / 2);  // most contacts of the relaxed fabric carry load
}
