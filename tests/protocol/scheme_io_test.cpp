// Scheme <-> JSON (lab units, JSON-pointer errors), result JSON/CSV columns, presets.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>

#include "engine/protocol/gradation.hpp"
#include "engine/protocol/paper_groups.hpp"
#include "server/io/result_csv.hpp"
#include "server/io/result_json.hpp"
#include "server/io/scheme_json.hpp"

using namespace triax;
using nlohmann::json;

TEST_CASE("empty scheme is the paper's group B defaults in lab units", "[protocol][io]") {
    const auto s = io::scheme_from_json(json::object());
    CHECK(s.specimen.diameter_m == Approx(0.1));
    CHECK(s.specimen.height_m == Approx(0.2));
    CHECK(s.specimen.target_porosity == Approx(0.35));
    CHECK(s.micro.friction == Approx(0.4));
    CHECK(s.micro.local_damping == Approx(0.7));
    CHECK(s.loading.confining_pressure_pa == Approx(100e3));
    CHECK(s.loading.stress_levels == std::vector<double>{0.1, 0.4, 0.6, 0.8});
    const json j = io::scheme_to_json(s);
    CHECK(j["loading"]["confining_pressure_kPa"].get<double>() == Approx(100.0));
    CHECK(j["specimen"]["diameter_mm"].get<double>() == Approx(100.0));
    CHECK(j["micro"]["normal_modulus_MPa"].get<double>() == Approx(230.15));
}

TEST_CASE("scheme round trip keeps every field", "[protocol][io]") {
    auto s = protocol::paper_group("E");
    s.gradation.kind = protocol::GradationSpec::Kind::SieveCurve;
    s.gradation.sieve_curve = {{0.5e-3, 0.0}, {1e-3, 10.0}, {10e-3, 60.0}, {20e-3, 100.0}};
    s.loading.stress_level_definition = protocol::StressLevelDefinition::PaperEq1;
    s.effects.seating_error = true;
    const auto back = io::scheme_from_json(io::scheme_to_json(s));
    CHECK(io::scheme_to_json(back) == io::scheme_to_json(s));
    CHECK(back.specimen.moisture_content == Approx(0.121));
    // Crushing fields travel in lab units (MPa, mm); presets have crushable grains.
    const json j = io::scheme_to_json(s);
    CHECK(j["micro"]["crushing_strength_MPa"].get<double>() == Approx(1.0));
    // The presets' cohesion: Mohr-Coulomb bonds of 500 kPa, and a crushing contact loses its bond.
    CHECK(j["micro"]["bond_shear_strength_kPa"].get<double>() == Approx(500.0));
    CHECK(j["micro"]["bond_friction"].get<double>() == Approx(0.4));
    CHECK(j["micro"]["crushing_breaks_bond"].get<bool>());
    CHECK(j["creep"]["bond_corrosion_rate_b1_per_s"].get<double>() == Approx(3e-10));
    CHECK(j["micro"]["crushing_reference_diameter_mm"].get<double>() == Approx(10.0));
    CHECK(back.micro.crushing_hardening_ratio == Approx(s.micro.crushing_hardening_ratio));
    CHECK(protocol::TestScheme{}.micro.crushing_strength_pa == 0.0);  // scheme default: unbreakable
    // The Mohr-Coulomb bond option travels too; the default is PFC's contact bond.
    CHECK(protocol::TestScheme{}.micro.bond_friction == 0.0);
    s.micro.bond_friction = 0.4;
    CHECK(io::scheme_from_json(io::scheme_to_json(s)).micro.bond_friction == Approx(0.4));
    CHECK_FALSE(protocol::TestScheme{}.micro.crushing_breaks_bond);
    s.micro.crushing_breaks_bond = true;
    CHECK(io::scheme_from_json(io::scheme_to_json(s)).micro.crushing_breaks_bond);
}

TEST_CASE("bad scheme fields are named by JSON pointer", "[protocol][io]") {
    auto field_of = [](const json& j) {
        try {
            io::scheme_from_json(j);
        } catch (const io::SchemeError& e) {
            return e.field;
        }
        return std::string("no error");
    };
    CHECK(field_of({{"specimen", {{"target_porosity", 0.9}}}}) == "/specimen/target_porosity");
    CHECK(field_of({{"specimen", {{"diameter_mm", "wide"}}}}) == "/specimen/diameter_mm");
    CHECK(field_of({{"loading", {{"stress_levels", {0.1, -0.4}}}}}) == "/loading/stress_levels/1");
    CHECK(field_of({{"loading", {{"confining_kpa", 100}}}}) == "/loading/confining_kpa");
    CHECK(field_of({{"micro", {{"crushing_weibull_modulus", 0.5}}}}) == "/micro/crushing_weibull_modulus");
    CHECK(field_of({{"micro", {{"bond_friction", -0.1}}}}) == "/micro/bond_friction");
    CHECK(field_of({{"micro", {{"crushing_hardening_ratio", -0.1}}}}) == "/micro/crushing_hardening_ratio");
    // Options that are not part of the model are unknown fields, not silently ignored.
    CHECK(field_of({{"creep", {{"grain_fatigue_time_s", 1.0e6}}}}) == "/creep/grain_fatigue_time_s");
    CHECK(field_of({{"micro", {{"crushing_breaks_bond", 1}}}}) == "/micro/crushing_breaks_bond");
    CHECK(field_of({{"loading", {{"stress_levels", {0.1, 0.4}}, {"stage_durations_min", {60}}}}}) ==
          "/loading/stage_durations_min");
    CHECK(field_of({{"gradation", {{"sieve_curve", {{{"size_mm", 2}, {"passing_pct", 50}}, {{"size_mm", 1}, {"passing_pct", 60}}}}}}}) ==
          "/gradation/sieve_curve/1");
}

TEST_CASE("presets are the five paper groups, D and E differ from B only in moisture", "[protocol][io]") {
    const json p = io::presets_to_json();
    REQUIRE(p["presets"].size() == 5);
    auto b = protocol::paper_group("B"), d = protocol::paper_group("D");
    json jb = io::scheme_to_json(b), jd = io::scheme_to_json(d);
    jb.erase("name");
    jd.erase("name");
    jd["specimen"]["moisture_content_pct"] = jb["specimen"]["moisture_content_pct"];
    CHECK(jb == jd);
    CHECK(protocol::paper_group("A").loading.confining_pressure_pa == Approx(50e3));
    CHECK(protocol::paper_group("C").loading.confining_pressure_pa == Approx(200e3));
    CHECK_THROWS_WITH(protocol::paper_group("F"), Catch::Contains("A, B, C, D, E"));
}

TEST_CASE("result series carry unit-suffixed columns in lab units", "[protocol][io]") {
    protocol::TestResult r;
    r.sigma3_pa = 100e3;
    r.shear.push_back({0.01, 200e3, 166.7e3, 300e3, 100e3, -0.002, 1e-4});
    protocol::CreepStageResult st;
    st.stage = 1;
    st.translated.push_back({600.0, 1e-3, 0.005});
    r.creep_stages.push_back(st);
    const json ss = io::result_series_to_json(r, "stress_strain");
    CHECK(ss["columns"][0] == "axial_strain_pct");
    CHECK(ss["rows"][0][0].get<double>() == Approx(1.0));
    CHECK(ss["rows"][0][1].get<double>() == Approx(200.0));
    const json cr = io::result_series_to_json(r, "creep");
    CHECK(cr["rows"][0][1].get<double>() == Approx(10.0));  // 600 s = 10 min
    CHECK(cr["rows"][0][2].get<double>() == Approx(1.0));   // 1 mm
    const std::string csv = io::result_series_to_csv(r, "volumetric");
    CHECK(csv.rfind("axial_strain_pct,volumetric_strain_pct\n", 0) == 0);
    CHECK(io::result_summary_to_json(r)["sigma3_kPa"].get<double>() == Approx(100.0));
    CHECK_THROWS(io::result_series_to_json(r, "nope"));
}

TEST_CASE("paper-group presets give a full-size DEM specimen of thousands of grains", "[protocol][io]") {
    // docs/parameters.md, "Paper-group gradation": Rmin = the paper's Eq. 2 radius 2.879 mm,
    // Rmax = 2 Rmin; the literal 0.5 mm x 39.7 gives ~140 grains of up to 40 mm.
    const auto s = protocol::paper_group("B");
    const double kPi = 3.14159265358979323846;
    const double solid = (1.0 - s.specimen.target_porosity) * kPi * 0.25 * s.specimen.diameter_m *
                         s.specimen.diameter_m * s.specimen.height_m;
    std::mt19937_64 rng(s.seed);
    const auto radii = protocol::draw_radii(s.gradation, solid, rng);
    const double r_max = *std::max_element(radii.begin(), radii.end());
    const double r_min = *std::min_element(radii.begin(), radii.end());
    CHECK(radii.size() > 2000);
    CHECK(radii.size() < 4000);
    CHECK(r_min >= 2.879e-3 * 0.999);
    CHECK(s.specimen.diameter_m / (2.0 * r_max) >= 6.0);  // the usual D / d_max for triaxial specimens
    std::mt19937_64 literal_rng(s.seed);
    auto literal = s.gradation;
    literal.r_min_m = 0.5e-3;
    literal.radius_ratio = 39.712;
    CHECK(protocol::draw_radii(literal, solid, literal_rng).size() < 300);
}

TEST_CASE("a scheme may start from a paper group and change only what differs", "[protocol][io]") {
    const auto c = protocol::paper_group("C");
    const auto s = io::scheme_from_json(json{{"preset", "C"}, {"seed", 3}, {"loading", {{"stress_levels", {0.2, 0.9}}}}});
    // The group's own fields...
    CHECK(s.loading.confining_pressure_pa == Approx(200e3));
    CHECK(s.micro.crushing_strength_pa == Approx(c.micro.crushing_strength_pa));
    CHECK(s.micro.bond_rolling_friction == Approx(c.micro.bond_rolling_friction));
    CHECK(s.gradation.r_min_m == Approx(c.gradation.r_min_m));
    CHECK(s.name == c.name);
    // ...and what the scheme names; new stages take the group's stage duration (2.5 days).
    CHECK(s.seed == 3);
    CHECK(s.loading.stress_levels == std::vector<double>{0.2, 0.9});
    CHECK(s.loading.stage_durations_s == std::vector<double>{c.loading.stage_durations_s.front(), c.loading.stage_durations_s.front()});
    // Without a preset the bare defaults stand.
    CHECK(io::scheme_from_json(json::object()).micro.crushing_strength_pa == 0.0);
    // An unknown group is named by its pointer.
    try {
        io::scheme_from_json(json{{"preset", "F"}});
        FAIL("no error for preset F");
    } catch (const io::SchemeError& e) {
        CHECK(e.field == "/preset");
        CHECK(std::string(e.what()).find("A, B, C, D, E") != std::string::npos);
    }
    CHECK_THROWS_AS(io::scheme_from_json(json{{"preset", 2}}), io::SchemeError);
}
