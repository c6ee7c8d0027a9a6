// The DEM forward model: parameter mapping onto the protocol's scheme (fast), and one
// reduced run timed (hidden). The whole loop on DEM data is dem_loop_test.cpp.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "engine/diagnose/dem_forward_model.hpp"
#include "engine/diagnose/lab_macro.hpp"
#include "engine/diagnose/diagnosis.hpp"
#include "engine/diagnose/packing_ensemble.hpp"
#include "engine/diagnose/residuals.hpp"
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

TEST_CASE("DEM forward model: a base without the catalog's effects, wide priors, shear to the lab's range", "[diagnose][dem]") {
    // A scheme that switches every catalog effect on (rolling resistance, the bonds' cement
    // neck, crushable grains, the creep law): the base the diagnosis calibrates has none of
    // them, so each can be tested, and the report names what was taken out.
    TestScheme base;
    base.effects.contact_creep_viscosity = true;
    base.effects.moisture_bonding = true;
    base.micro.rolling_friction = 0.2;
    base.micro.bond_rolling_friction = 0.6;
    base.micro.crushing_strength_pa = 1.0e6;
    const DemForwardModel model(base, lab_conditions(), 1, 300);
    CHECK_FALSE(model.includes(Effect::RollingResistance));
    CHECK_FALSE(model.includes(Effect::BondDegradation));
    CHECK_FALSE(model.includes(Effect::ContactCreepViscosity));
    CHECK(model.includes(Effect::MoistureBonding));  // the base calibrates bonds from 0
    CHECK_THAT(model.not_offered_reason(Effect::MoistureBonding), Catch::Contains("from 0"));
    REQUIRE(model.effect_parameters(Effect::RollingResistance).size() == 1);
    REQUIRE(model.effect_parameters(Effect::ContactCreepViscosity).size() == 1);
    // Seating strain becomes deformation on the model's own specimen height.
    CHECK(model.specimen_height_m() == Approx(base.specimen.height_m));
    const ParameterSpec creep_spec = model.effect_parameters(Effect::ContactCreepViscosity).front();
    CHECK(creep_spec.name == "direct_effect_a");
    CHECK(creep_spec.lower_is_off);  // 0 = no creep: the base
    // No lab creep per decade to read: the reference a.
    CHECK(creep_spec.nominal == Approx(kCreepRefA));
    CHECK(creep_spec.upper == Approx(kCreepDirectEffectMax));

    const auto held = model.held_fixed();
    auto held_named = [&](const std::string& n) {
        return std::any_of(held.begin(), held.end(), [&](const HeldParameter& h) { return h.name == n; });
    };
    CHECK(held_named("bond_rolling_friction"));
    CHECK(held_named("crushing_strength"));
    CHECK(held_named("local_damping"));

    const auto specs = model.base_parameters();
    REQUIRE(specs.size() == 4);  // modulus, friction, bond strength, density; creep is an effect
    CHECK(specs[0].name == "contact_normal_modulus");
    CHECK(specs[0].upper / specs[0].lower == Approx(100.0));  // two decades
    CHECK(specs[1].lower == Approx(0.05));
    CHECK(specs[1].upper == Approx(1.0));
    CHECK(specs[2].name == "bond_strength");
    CHECK(specs[2].lower == 0.0);  // cohesionless allowed
    CHECK(specs[3].name == "compaction_friction_ratio");
    CHECK(specs[3].lower == 0.0);  // frictionless: the densest packing
    CHECK(specs[3].upper == 1.0);  // the grains' own friction: the loosest
    CHECK(held_named("generation_porosity"));  // grown loose; the compaction gives the density
    CHECK_FALSE(held_named("compaction_friction_ratio"));  // calibrated, not held

    ModelPoint p{{2.0 * base.micro.normal_modulus_pa, 0.55, 120e3, 0.44}, {{Effect::RollingResistance, {0.25}}}};
    const TestScheme s = model.scheme_for(p, 200e3);
    CHECK(s.loading.confining_pressure_pa == 200e3);
    CHECK(s.micro.normal_modulus_pa == Approx(2.0 * base.micro.normal_modulus_pa));
    CHECK(s.micro.shear_modulus_pa / s.micro.normal_modulus_pa == Approx(base.micro.shear_modulus_pa / base.micro.normal_modulus_pa));
    CHECK(s.micro.friction == Approx(0.55));
    CHECK(s.micro.bond_normal_strength_pa == Approx(120e3));
    CHECK(s.micro.bond_shear_strength_pa == Approx(120e3));
    CHECK(s.micro.bond_rolling_friction == 0.0);
    CHECK(s.micro.crushing_strength_pa == 0.0);
    CHECK_FALSE(s.effects.contact_creep_viscosity);
    CHECK(s.micro.rolling_friction == Approx(0.25));
    CHECK(s.max_particles == 300);
    CHECK(s.specimen.target_porosity == Approx(kDiagnosisGenerationPorosity));
    CHECK(s.specimen.compaction_friction_ratio == Approx(0.44));

    // The creep effect is the creep law switched on with its rate sensitivity a; 0 is the
    // base without creep, so the base's runs are the effect's runs at 0.
    ModelPoint creep{p.base, {{Effect::ContactCreepViscosity, {0.025}}}};
    const TestScheme sc = model.scheme_for(creep, 200e3);
    CHECK(sc.effects.contact_creep_viscosity);
    CHECK(sc.effects.viscosity_scale == 1.0);  // the scheme's rate
    CHECK(sc.creep.direct_effect_a == Approx(0.025));
    const TestScheme off = model.scheme_for(ModelPoint{p.base, {{Effect::ContactCreepViscosity, {0.0}}}}, 200e3);
    CHECK_FALSE(off.effects.contact_creep_viscosity);
    CHECK_THROWS_WITH(model.scheme_for(ModelPoint{p.base, {{Effect::ContactCreepViscosity, {-0.01}}}}, 200e3),
                      Catch::Contains("direct_effect_a"));

    ModelPoint bad{{1.0, 0.5}, {}};
    CHECK_THROWS_WITH(model.scheme_for(bad, 100e3), Catch::Contains("base parameters"));
    ModelPoint artefact{p.base, {{Effect::SeatingError, {0.01}}}};
    CHECK_THROWS_WITH(model.scheme_for(artefact, 100e3), Catch::Contains("test artefact"));
}

TEST_CASE("DEM forward model: grain breakage is crushing and offered on shear data, creep viscosity is not", "[diagnose][dem]") {
    // Grain breakage maps onto crushable grains (crushability x = 0.6 MPa / sigma0, off at
    // 0), which act in shear: offered on shear-only data. Contact creep viscosity acts in
    // time: on shear curves alone it cannot be seen, so it is not a candidate there.
    TestScheme base;
    const DemForwardModel shear_model(base, shear_conditions({100e3}), 1, 0);
    const auto crush = shear_model.effect_parameters(Effect::BondDegradation);
    REQUIRE(crush.size() == 1);
    CHECK(crush[0].name == "grain_crushability");
    CHECK(crush[0].lower == 0.0);
    CHECK(crush[0].lower_is_off);
    CHECK(crush[0].upper == Approx(kCrushabilityMax));
    CHECK(crush[0].nominal == Approx(1.0));  // a 0.6 MPa grain
    CHECK(shear_model.effect_parameters(Effect::ContactCreepViscosity).empty());
    CHECK_THAT(shear_model.not_offered_reason(Effect::ContactCreepViscosity), Catch::Contains("no creep curve"));

    const auto nominal = [&](const DemForwardModel& m) {
        std::vector<double> v;
        for (const auto& s : m.base_parameters()) v.push_back(s.nominal);
        return v;
    };
    const TestScheme s1 = shear_model.scheme_for({nominal(shear_model), {{Effect::BondDegradation, {0.75}}}}, 200e3);
    CHECK(s1.micro.crushing_strength_pa == Approx(0.8e6));
    CHECK(s1.micro.crushing_weibull_modulus == base.micro.crushing_weibull_modulus);
    CHECK(s1.micro.crushing_hardening_ratio == base.micro.crushing_hardening_ratio);
    CHECK_FALSE(s1.effects.accelerated_bond_corrosion);  // creep bond damage untouched
    const TestScheme s0 = shear_model.scheme_for({nominal(shear_model), {{Effect::BondDegradation, {0.0}}}}, 200e3);
    CHECK(s0.micro.crushing_strength_pa == 0.0);
    CHECK_THROWS_WITH(shear_model.scheme_for({nominal(shear_model), {{Effect::BondDegradation, {-0.5}}}}, 200e3),
                      Catch::Contains("grain_crushability"));

    // The shear runs to 2 % past the lab's last reading, without the softening stop.
    LabDataset to_12 = shear_conditions({100e3}, 0.12);
    const DemForwardModel far(base, to_12, 1, 0);
    const TestScheme s12 = far.scheme_for({nominal(far), {}}, 100e3);
    CHECK(s12.loading.stop_at_softening);  // scheme_for leaves the loading; simulate() sets it
    // One pressure: the envelope runs through the origin, so no cohesion is claimed and the
    // bond strength is held at 0, not calibrated.
    const auto far_specs = far.base_parameters();
    CHECK(std::none_of(far_specs.begin(), far_specs.end(), [](const ParameterSpec& p) { return p.name == "bond_strength"; }));
    const auto far_held = far.held_fixed();
    CHECK(std::any_of(far_held.begin(), far_held.end(), [](const HeldParameter& h) { return h.name == "bond_strength" && h.value == 0.0; }));
    CHECK_FALSE(far.includes(Effect::MoistureBonding));
    CHECK_THAT(far.not_offered_reason(Effect::MoistureBonding), Catch::Contains("no cohesion"));
    CHECK(s12.micro.bond_normal_strength_pa == 0.0);

    // With creep curves: a second parameter, extra bond damage in the creep holds
    // (bond_corrosion_scale = 1 + e), off at 0 too.
    const DemForwardModel creep_model(base, lab_conditions(), 1, 0);
    const auto both = creep_model.effect_parameters(Effect::BondDegradation);
    REQUIRE(both.size() == 2);
    CHECK(both[1].name == "extra_bond_damage_rate");
    CHECK(both[1].lower_is_off);
    const TestScheme s2 = creep_model.scheme_for({nominal(creep_model), {{Effect::BondDegradation, {0.5, 2.0}}}}, 200e3);
    CHECK(s2.micro.crushing_strength_pa == Approx(1.2e6));
    CHECK(s2.effects.accelerated_bond_corrosion);
    CHECK(s2.effects.bond_corrosion_scale == Approx(3.0));
}

TEST_CASE("DEM forward model: a lab's relative density holds the packing density", "[diagnose]") {
    const TestScheme base;
    CHECK(compaction_friction_for(0.0) == 1.0);  // loosest: consolidated at the grains' friction
    CHECK(compaction_friction_for(1.0) == 0.0);  // densest: frictionless
    const DemForwardModel stated(base, shear_conditions({100e3}), 1, 0, nullptr, 1, 0.5);
    const auto specs = stated.base_parameters();
    REQUIRE(specs.size() == 2);  // modulus, friction: the density is the lab's, no cohesion at one pressure
    CHECK(std::none_of(specs.begin(), specs.end(), [](const ParameterSpec& p) { return p.name == "compaction_friction_ratio"; }));
    const auto held = stated.held_fixed();
    const auto h = std::find_if(held.begin(), held.end(), [](const HeldParameter& p) { return p.name == "compaction_friction_ratio"; });
    REQUIRE(h != held.end());
    CHECK(h->value == Approx(0.5));
    CHECK_THAT(h->why, Catch::Contains("relative density"));
    const TestScheme s = stated.scheme_for({{base.micro.normal_modulus_pa, 0.5}, {}}, 100e3);
    CHECK(s.specimen.compaction_friction_ratio == Approx(0.5));
    CHECK_THROWS_WITH(DemForwardModel(base, shear_conditions({100e3}), 1, 0, nullptr, 1, 1.2),
                      Catch::Contains("relative density"));
}

// The lever the calibration has over the curve's shape: consolidated at the grains' own
// friction the base's packing contracts further in shear than consolidated frictionless
// (docs/diagnosis.md section 6; bench/base_reach porosity=0.45 compaction=0,1: largest
// contraction 0.03-0.04 % against 1.2-2.2 %, seeds 1-3, to 15 %).
TEST_CASE("DEM forward model: the loose base contracts more in shear than the dense one", "[diagnose][dem]") {
    TestScheme base = reduced_scheme(2.5e-3, 0.04, 3);
    base.micro.bond_normal_strength_pa = base.micro.bond_shear_strength_pa = 0.0;
    const LabDataset lab = shear_conditions({100e3}, 0.04);
    const DemForwardModel model(base, lab, 1, 200);
    std::vector<double> v;
    for (const auto& s : model.base_parameters()) v.push_back(s.nominal);
    REQUIRE(v.size() == 3);  // modulus, friction, compaction: one pressure shows no cohesion
    v[1] = 0.3;
    auto largest_contraction = [&](double compaction_friction_ratio, std::uint64_t seed) {
        std::vector<double> p = v;
        p[2] = compaction_friction_ratio;
        const LabDataset out = model.simulate({p, {}}, seed);
        REQUIRE(out.curves.size() == 1);
        const auto& ev = out.curves[0].volumetric_strain;
        REQUIRE(!ev.empty());
        return *std::max_element(ev.begin(), ev.end());
    };
    for (std::uint64_t seed : {1, 2}) {
        const double dense = largest_contraction(0.0, seed);
        const double loose = largest_contraction(1.0, seed);
        INFO("seed " << seed << ": largest contraction dense " << 100 * dense << " %, loose " << 100 * loose << " %");
        CHECK(loose > dense + 0.002);
    }
}

TEST_CASE("DEM forward model: every pressure's shear reaches the lab's last reading (15 %)", "[diagnose][dem]") {
    // A weak cohesionless material read to 15 % at three pressures: the model's curves must
    // cover the lab's range (no softening stop), or the readings past its end count as
    // unreached instead of misfit.
    TestScheme base = reduced_scheme(2.5e-3, 0.15, 3);
    base.micro.bond_normal_strength_pa = base.micro.bond_shear_strength_pa = 0.0;
    const LabDataset lab = shear_conditions({50e3, 100e3, 200e3}, 0.15);
    const DemForwardModel model(base, lab, 1, 150);
    std::vector<double> v;
    for (const auto& s : model.base_parameters()) v.push_back(s.nominal);
    v[1] = 0.2;  // weak: low friction
    const LabDataset out = model.simulate({v, {}}, 3);
    REQUIRE(out.curves.size() == 3);
    for (const auto& c : out.curves) {
        REQUIRE(!c.axial_strain.empty());
        CHECK(c.axial_strain.back() >= 0.15);
        CHECK(c.deviator_pa.back() > 0.0);
    }
    const auto layout = residual_layout(lab);
    const auto r = normalised_residual(layout, out);
    for (double x : r) CHECK(x != 1.0);  // every reading reached
}

TEST_CASE("DEM forward model: a run of two packings is the mean of the two packings' runs", "[diagnose][dem]") {
    TestScheme base = reduced_scheme(2.5e-3, 0.01, 3);
    base.micro.bond_normal_strength_pa = base.micro.bond_shear_strength_pa = 0.0;
    const LabDataset lab = shear_conditions({100e3}, 0.01);
    const DemForwardModel one(base, lab, 1, 120);
    const DemForwardModel two(base, lab, 1, 120, nullptr, 2);
    std::vector<double> v;
    for (const auto& s : one.base_parameters()) v.push_back(s.nominal);
    const LabDataset a = one.simulate({v, {}}, 5);
    const LabDataset b = one.simulate({v, {}}, 5 + kPackingSeedStride);
    const LabDataset m = two.simulate({v, {}}, 5);
    REQUIRE(m.curves.size() == 1);
    const auto& ca = a.curves[0];
    const auto& cb = b.curves[0];
    const auto& cm = m.curves[0];
    CHECK(ca.deviator_pa != cb.deviator_pa);  // two packings
    REQUIRE(cm.axial_strain.size() >= 3);
    // Every reading of the mean (the first packing's strains, up to the shorter curve's end)
    // is the mean of the two packings' curves read there.
    auto read = [](const LabCurve& c, double e) {
        const auto j = static_cast<std::size_t>(std::lower_bound(c.axial_strain.begin(), c.axial_strain.end(), e) -
                                                c.axial_strain.begin());
        if (j == 0) return c.deviator_pa.front();
        const double w = (e - c.axial_strain[j - 1]) / (c.axial_strain[j] - c.axial_strain[j - 1]);
        return (1 - w) * c.deviator_pa[j - 1] + w * c.deviator_pa[j];
    };
    CHECK(cm.axial_strain.back() <= std::min(ca.axial_strain.back(), cb.axial_strain.back()));
    for (std::size_t i = 0; i < cm.axial_strain.size(); ++i)
        CHECK(cm.deviator_pa[i] == Approx(0.5 * (read(ca, cm.axial_strain[i]) + read(cb, cm.axial_strain[i]))).margin(1e-6));
    CHECK_THROWS(DemForwardModel(base, lab, 1, 120, nullptr, 0));
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

TEST_CASE("DEM forward model: the creep effect starts from the lab's creep per decade", "[diagnose][dem]") {
    // The lab's per-decade slope is read from the first minute on, by least squares in log t.
    const std::vector<double> t{30.0, 60.0, 600.0, 6000.0, 60000.0};
    const std::vector<double> e{0.0005, 0.001, 0.002, 0.003, 0.004};
    CHECK(creep_strain_per_decade(t, e) == Approx(0.001));
    CHECK(creep_strain_per_decade({60.0, 600.0}, {0.0, 0.001}) == 0.0);  // two readings: none
    // Monotone in the lab's creep, the reference a at the reference creep, within its range.
    CHECK(creep_direct_effect_for(kCreepPerDecadeAtRef) == Approx(kCreepRefA));
    CHECK(creep_direct_effect_for(2.0 * kCreepPerDecadeAtRef) > kCreepRefA);
    CHECK(creep_direct_effect_for(1e-9) == Approx(kCreepDirectEffectMin));
    CHECK(creep_direct_effect_for(1.0) == Approx(kCreepDirectEffectMax));
}
