// The DEM forward model: parameter mapping onto the protocol's scheme (fast), and the
// whole loop on a reduced DEM specimen with a hidden effect (slow, shear only).
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "engine/diagnose/dem_forward_model.hpp"
#include "engine/diagnose/diagnosis.hpp"
#include "engine/protocol/test_scheme.hpp"
#include "synthetic_lab.hpp"

using namespace triax::diagnose;
using triax::protocol::TestScheme;

namespace {
// The protocol tests' reduced specimen: 50 x 100 mm, ~200 grains of 2.5-7.5 mm radius.
TestScheme reduced_scheme() {
    TestScheme s;
    s.name = "reduced";
    s.specimen.diameter_m = 0.05;
    s.specimen.height_m = 0.1;
    s.gradation.r_min_m = 2.5e-3;
    s.gradation.radius_ratio = 3.0;
    s.loading.max_axial_strain = 0.08;
    s.seed = 11;
    return s;
}

LabDataset lab_conditions() {
    LabDataset lab;
    for (double s3 : {50e3, 200e3}) {
        LabCurve c;
        c.kind = CurveKind::Shear;
        c.confining_pa = s3;
        c.axial_strain = {0.0, 0.01, 0.02};
        c.deviator_pa = {0.0, 1e5, 2e5};
        lab.curves.push_back(c);
    }
    LabCurve cr;
    cr.kind = CurveKind::Creep;
    cr.stage = 2;
    cr.stress_level = 0.45;
    cr.confining_pa = 200e3;
    cr.time_s = {0.0, 600.0, 3000.0};
    cr.axial_strain = {1e-3, 1.1e-3, 1.2e-3};
    lab.curves.push_back(cr);
    return lab;
}
}  // namespace

TEST_CASE("DEM forward model maps parameters onto the scheme and skips effects already on", "[diagnose][dem]") {
    TestScheme base;
    base.effects.contact_creep_viscosity = true;
    base.effects.moisture_bonding = true;
    base.effects.rolling_resistance = false;
    const DemForwardModel model(base, lab_conditions(), 1, 300);
    CHECK(model.includes(Effect::MoistureBonding));
    CHECK(model.includes(Effect::ContactCreepViscosity));
    CHECK_FALSE(model.includes(Effect::RollingResistance));
    CHECK(model.effect_parameters(Effect::MoistureBonding).empty());
    REQUIRE(model.effect_parameters(Effect::RollingResistance).size() == 1);

    const auto specs = model.base_parameters();
    REQUIRE(specs.size() == 4);  // modulus, friction, bond strength, creep slip rate (lab has creep)
    CHECK(specs[0].name == "contact_normal_modulus");
    CHECK(specs[3].name == "creep_slip_rate_scale");

    ModelPoint p{{2.0 * base.micro.normal_modulus_pa, 0.55, 3.0, 10.0}, {{Effect::RollingResistance, {0.25}}}};
    const TestScheme s = model.scheme_for(p, 200e3);
    CHECK(s.loading.confining_pressure_pa == 200e3);
    CHECK(s.micro.normal_modulus_pa == Approx(2.0 * base.micro.normal_modulus_pa));
    CHECK(s.micro.shear_modulus_pa / s.micro.normal_modulus_pa == Approx(base.micro.shear_modulus_pa / base.micro.normal_modulus_pa));
    CHECK(s.micro.friction == Approx(0.55));
    CHECK(s.micro.bond_normal_strength_pa == Approx(3.0 * base.micro.bond_normal_strength_pa));
    CHECK(s.creep.slip_rate_a_m_s == Approx(10.0 * base.creep.slip_rate_a_m_s));
    CHECK(s.effects.rolling_resistance);
    CHECK(s.effects.rolling_friction == Approx(0.25));
    CHECK(s.max_particles == 300);

    ModelPoint bad{{1.0, 0.5}, {}};
    CHECK_THROWS_WITH(model.scheme_for(bad, 100e3), Catch::Contains("base parameters"));
    ModelPoint artefact{p.base, {{Effect::SeatingError, {0.01}}}};
    CHECK_THROWS_WITH(model.scheme_for(artefact, 100e3), Catch::Contains("test artefact"));
}

TEST_CASE("DEM forward model: creep-only effects are not offered on shear-only data", "[diagnose][dem]") {
    // The protocol applies grain breakage (breakage_damage_scale) to the creep damage rate
    // only, and contact creep viscosity acts in time: on shear curves alone neither can be
    // seen (measured: identical shear curves with and without breakage), so neither is a
    // candidate there, and the base model gets no creep slip-rate parameter.
    TestScheme base;
    base.effects.contact_creep_viscosity = false;
    LabDataset shear_only;
    LabCurve c;
    c.kind = CurveKind::Shear;
    c.confining_pa = 100e3;
    c.axial_strain = {0.0, 0.01, 0.02};
    c.deviator_pa = {0.0, 1e5, 2e5};
    shear_only.curves.push_back(c);
    const DemForwardModel shear_model(base, shear_only, 1, 0);
    CHECK(shear_model.effect_parameters(Effect::BondDegradation).empty());
    CHECK(shear_model.effect_parameters(Effect::ContactCreepViscosity).empty());
    CHECK(shear_model.effect_parameters(Effect::RollingResistance).size() == 1);

    const DemForwardModel creep_model(base, lab_conditions(), 1, 0);
    REQUIRE(creep_model.effect_parameters(Effect::BondDegradation).size() == 1);
    CHECK(creep_model.effect_parameters(Effect::BondDegradation)[0].name == "breakage_damage_scale");
    CHECK(creep_model.effect_parameters(Effect::ContactCreepViscosity).size() == 1);

    // Physical priors of the base parameters (docs/diagnosis.md section 6): friction of
    // mineral grains, bond strength within a factor 3 of the moisture relation.
    const auto specs = shear_model.base_parameters();
    REQUIRE(specs.size() == 3);
    CHECK(specs[1].lower == Approx(0.1));
    CHECK(specs[1].upper == Approx(0.7));
    CHECK(specs[2].name == "bond_strength_scale");
    CHECK(specs[2].lower == Approx(1.0 / 3.0));
    CHECK(specs[2].upper == Approx(3.0));
}

TEST_CASE("DEM forward model: one reduced shear run, timed", "[diagnose][dem][.timing]") {
    TestScheme base = reduced_scheme();
    LabDataset lab;
    LabCurve c;
    c.kind = CurveKind::Shear;
    c.confining_pa = 100e3;
    c.axial_strain = {0.0, 0.05, 0.1};
    c.deviator_pa = {0.0, 1e5, 2e5};
    lab.curves.push_back(c);
    const DemForwardModel model(base, lab, 1, 0);
    std::vector<double> nominal;
    for (const auto& s : model.base_parameters()) nominal.push_back(s.nominal);
    const auto t0 = std::chrono::steady_clock::now();
    const auto out = model.simulate({nominal, {}}, 1);
    const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    REQUIRE(out.curves.size() == 1);
    const auto& sh = out.curves[0];
    std::string text = "run took " + std::to_string(dt) + " s, " + std::to_string(sh.axial_strain.size()) + " points\n";
    for (std::size_t i = 0; i < sh.axial_strain.size(); i += std::max<std::size_t>(1, sh.axial_strain.size() / 15))
        text += std::to_string(sh.axial_strain[i]) + " " + std::to_string(sh.deviator_pa[i]) + " " +
                std::to_string(sh.volumetric_strain[i]) + "\n";
    WARN(text);
}
