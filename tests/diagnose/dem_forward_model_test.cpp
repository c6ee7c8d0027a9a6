// The DEM forward model: parameter mapping onto the protocol's scheme (fast), and one
// reduced run timed (hidden). The whole loop on DEM data is dem_loop_test.cpp.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "engine/diagnose/dem_forward_model.hpp"
#include "engine/diagnose/diagnosis.hpp"
#include "engine/protocol/test_scheme.hpp"
#include "lab_fixtures.hpp"

using namespace triax::diagnose;
using namespace triax::diagnose::testing;
using triax::protocol::TestScheme;

namespace {
// Two shear curves (50, 200 kPa) and a creep stage at 200 kPa.
LabDataset lab_conditions() {
    LabDataset lab = shear_conditions({50e3, 200e3});
    lab.curves.push_back(creep_curve(2, 200e3, {0.0, 600.0, 3000.0}, {1e-3, 1.1e-3, 1.2e-3}, 0.45));
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

TEST_CASE("DEM forward model: grain breakage is crushing and offered on shear data, creep viscosity is not", "[diagnose][dem]") {
    // Grain breakage maps onto crushable grains (crushability x = 0.6 MPa / sigma0, off at
    // 0), which act in shear: offered on shear-only data. Contact creep viscosity acts in
    // time: on shear curves alone it cannot be seen, so it is not a candidate there, and
    // the base model gets no creep slip-rate parameter.
    TestScheme base;
    base.effects.contact_creep_viscosity = false;
    const DemForwardModel shear_model(base, shear_conditions({100e3}), 1, 0);
    CHECK_FALSE(shear_model.includes(Effect::BondDegradation));
    const auto crush = shear_model.effect_parameters(Effect::BondDegradation);
    REQUIRE(crush.size() == 1);
    CHECK(crush[0].name == "grain_crushability");
    CHECK(crush[0].lower == 0.0);
    CHECK(crush[0].lower_is_off);
    CHECK(crush[0].upper == Approx(kCrushabilityMax));
    CHECK(crush[0].nominal == Approx(1.0));  // a 0.6 MPa grain (the presets' of sessions 8-11)
    CHECK(shear_model.effect_parameters(Effect::ContactCreepViscosity).empty());
    CHECK(shear_model.effect_parameters(Effect::RollingResistance).size() == 1);

    const auto nominal = [&](const DemForwardModel& m) {
        std::vector<double> v;
        for (const auto& s : m.base_parameters()) v.push_back(s.nominal);
        return v;
    };
    // x -> sigma0 = 0.6 MPa / x; x = 0 is unbreakable (the scheme without the effect);
    // the presets' Weibull modulus, reference diameter and hardening are kept.
    const TestScheme s1 = shear_model.scheme_for({nominal(shear_model), {{Effect::BondDegradation, {0.75}}}}, 200e3);
    CHECK(s1.micro.crushing_strength_pa == Approx(0.8e6));
    CHECK(s1.micro.crushing_weibull_modulus == base.micro.crushing_weibull_modulus);
    CHECK(s1.micro.crushing_hardening_ratio == base.micro.crushing_hardening_ratio);
    CHECK_FALSE(s1.effects.accelerated_bond_corrosion);  // creep bond damage untouched
    const TestScheme s0 = shear_model.scheme_for({nominal(shear_model), {{Effect::BondDegradation, {0.0}}}}, 200e3);
    CHECK(s0.micro.crushing_strength_pa == 0.0);
    CHECK_THROWS_WITH(shear_model.scheme_for({nominal(shear_model), {{Effect::BondDegradation, {-0.5}}}}, 200e3),
                      Catch::Contains("grain_crushability"));

    // With creep curves of a bonded specimen: a second parameter, extra bond damage in the
    // creep holds (bond_corrosion_scale = 1 + e), off at 0 too.
    const DemForwardModel creep_model(base, lab_conditions(), 1, 0);
    const auto both = creep_model.effect_parameters(Effect::BondDegradation);
    REQUIRE(both.size() == 2);
    CHECK(both[1].name == "extra_bond_damage_rate");
    CHECK(both[1].lower_is_off);
    CHECK(creep_model.effect_parameters(Effect::ContactCreepViscosity).size() == 1);
    const TestScheme s2 = creep_model.scheme_for({nominal(creep_model), {{Effect::BondDegradation, {0.5, 2.0}}}}, 200e3);
    CHECK(s2.micro.crushing_strength_pa == Approx(1.2e6));
    CHECK(s2.effects.accelerated_bond_corrosion);
    CHECK(s2.effects.bond_corrosion_scale == Approx(3.0));

    // Crushable grains already in the scheme (the paper-group presets): breakage is part
    // of the base model and not proposed again.
    TestScheme crushable = base;
    crushable.micro.crushing_strength_pa = 0.6e6;
    const DemForwardModel preset_model(crushable, shear_conditions({100e3}), 1, 0);
    CHECK(preset_model.includes(Effect::BondDegradation));
    CHECK(preset_model.effect_parameters(Effect::BondDegradation).empty());

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
    // The protocol tests' reduced specimen: ~200 grains of 2.5-7.5 mm radius, to 8 %.
    const DemForwardModel model(reduced_scheme(2.5e-3, 0.08, 11), shear_conditions({100e3}, 0.1), 1, 0);
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
