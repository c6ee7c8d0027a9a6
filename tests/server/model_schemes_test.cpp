// The final model's schemes (server/diagnoses/model_schemes.hpp): the DEM model the
// diagnosis calibrated, built by DemForwardModel from a report's parameters, one scheme per
// lab condition, each POSTable to /runs; and the service storing them with the report (or
// the report without them). No DEM run: the reports are made up, the engine only builds
// schemes (diagnosis_e2e_test.cpp checks a real diagnosis's).
// Eigen (through the engine's headers) before the fixture's socket headers: <resolv.h>
// defines `_res`, a name Eigen's products use.
#include "engine/diagnose/dem_forward_model.hpp"
#include "server/diagnoses/model_schemes.hpp"
#include "server/io/diagnosis_json.hpp"
#include "server/io/scheme_json.hpp"

#include "service_fixture.hpp"

using namespace triax::test;
using namespace triax::diagnose;
using triax::service::model_schemes_json;

namespace {

LabCurve shear_curve(double confining_kpa, double last_strain) {
    LabCurve c;
    c.confining_pa = confining_kpa * 1e3;
    for (int i = 1; i <= 10; ++i) {
        const double e = last_strain * i / 10.0;
        c.axial_strain.push_back(e);
        // A cohesive fill: peak q = 2 sigma3 + 100 kPa, an envelope intercept c' of 29 kPa,
        // so the base calibrates its bonds (held at 0 where the lab shows no cohesion).
        c.deviator_pa.push_back((confining_kpa * 1e3 * 2.0 + 100e3) * (1.0 - std::exp(-e / 0.01)));
    }
    return c;
}

LabCurve creep_curve(double confining_kpa, int stage, double stress_level, double last_min) {
    LabCurve c;
    c.kind = CurveKind::Creep;
    c.stage = stage;
    c.confining_pa = confining_kpa * 1e3;
    c.stress_level = stress_level;
    for (int i = 0; i <= 10; ++i) {
        c.time_s.push_back(60.0 * last_min * i / 10.0);
        c.axial_strain.push_back(1e-3 * stage + 1e-4 * std::log1p(i));
    }
    return c;
}

// Shear to 5 % at 100 kPa; shear to 8 % and two creep stages at 200 kPa.
LabDataset two_conditions() {
    LabDataset lab;
    lab.curves = {shear_curve(100, 0.05), shear_curve(200, 0.08), creep_curve(200, 1, 0.4, 100),
                  creep_curve(200, 2, 0.7, 200)};
    return lab;
}

triax::protocol::TestScheme user_scheme() {
    return triax::io::scheme_from_json(json::parse(R"({
      "name": "fill", "seed": 3, "max_particles": 0,
      "specimen": {"lateral_boundary": "bonded_membrane"},
      "micro": {"normal_modulus_MPa": 100, "shear_modulus_MPa": 50, "rolling_friction": 0.3, "bond_rolling_friction": 0.2},
      "effects": {"membrane_thickness_mm": 0.5}})"));
}

FittedParameter param(const std::string& name, double value) { return {name, "", value, 0.0}; }

}  // namespace

TEST_CASE("the final model's schemes are the calibrated DEM model, one per lab condition", "[server][diagnosis]") {
    const auto scheme = user_scheme();
    const auto lab = two_conditions();
    DiagnoseOptions options;
    options.max_particles = 150;
    options.seed = 7;
    DiagnosisReport report;
    // seating_error named; membrane_compliance kept as a correction below the naming
    // threshold: in `parameters` (and the report's curves) but not in `effects`.
    report.effects = {"rolling_resistance", "bond_degradation", "contact_creep_viscosity", "seating_error"};
    report.parameters = {param("contact_normal_modulus", 1.5e8), param("friction", 0.6), param("bond_strength", 2e4),
                         param("compaction_friction_ratio", 0.4), param("rolling_friction", 0.15),
                         param("grain_crushability", 0.5), param("extra_bond_damage_rate", 0.0),
                         param("direct_effect_a", 0.02), param("seating_strain", 0.004),
                         param("membrane_stiffness", 5e4)};
    const json out = model_schemes_json(scheme, lab, options, report);
    REQUIRE(out.size() == 2);
    CHECK(out[0]["confining_kPa"].get<double>() == Approx(100.0));
    CHECK(out[1]["confining_kPa"].get<double>() == Approx(200.0));
    for (const auto& c : out) {
        const json& s = c["scheme"];
        INFO(s.dump());
        // POSTable as it is: what POST /runs parses.
        CHECK_NOTHROW(triax::io::scheme_from_json(s));
        CHECK(s["loading"]["confining_pressure_kPa"].get<double>() == Approx(c["confining_kPa"].get<double>()));
        // The diagnosis's base: grain pressure, the loose packing, the options' cap and seed.
        CHECK(s["specimen"]["lateral_boundary"] == "grain_pressure");
        CHECK(s["specimen"]["target_porosity"].get<double>() == Approx(kDiagnosisGenerationPorosity));
        CHECK(s["max_particles"] == 150);
        CHECK(s["seed"] == 7);
        CHECK(s["micro"]["bond_rolling_friction"].get<double>() == 0.0);
        // The calibrated base parameters (E_s keeps the scheme's ratio 1/2).
        CHECK(s["micro"]["normal_modulus_MPa"].get<double>() == Approx(150.0));
        CHECK(s["micro"]["shear_modulus_MPa"].get<double>() == Approx(75.0));
        CHECK(s["micro"]["friction"].get<double>() == 0.6);
        CHECK(s["micro"]["bond_normal_strength_kPa"].get<double>() == Approx(20.0));
        CHECK(s["micro"]["bond_shear_strength_kPa"].get<double>() == Approx(20.0));
        CHECK(s["specimen"]["compaction_friction_ratio"].get<double>() == 0.4);
        // The physical effects as scheme_for sets them.
        CHECK(s["micro"]["rolling_friction"].get<double>() == 0.15);
        CHECK(s["micro"]["crushing_strength_MPa"].get<double>() == Approx(0.6 / 0.5));
        CHECK(s["effects"]["accelerated_bond_corrosion"] == false);
        CHECK(s["effects"]["contact_creep_viscosity"] == true);
        CHECK(s["creep"]["direct_effect_a"].get<double>() == Approx(0.02));
        // The artefacts through the protocol: strain + s at the platen, q + K_m eps_a.
        CHECK(s["effects"]["seating_error"] == true);
        CHECK(s["effects"]["seating_displacement_mm"].get<double>() == Approx(0.004 * s["specimen"]["height_mm"].get<double>()));
        CHECK(s["effects"]["membrane_compliance"] == true);
        const double km = 4.0 * s["effects"]["membrane_modulus_kPa"].get<double>() * 1e3 *
                          s["effects"]["membrane_thickness_mm"].get<double>() / s["specimen"]["diameter_mm"].get<double>();
        CHECK(km == Approx(5e4));
    }
    // Each condition as the diagnosis ran it: shear 2 % past the lab's last reading with no
    // softening stop; creep stages only where the lab has creep curves.
    const json& at100 = out[0]["scheme"]["loading"];
    const json& at200 = out[1]["scheme"]["loading"];
    CHECK(out[0]["scheme"]["name"] == "fill (calibrated, 100 kPa)");
    CHECK(at100["max_axial_strain_pct"].get<double>() == Approx(5.1));
    CHECK(at100["stop_at_softening"] == false);
    CHECK(at100["stress_levels"].empty());
    CHECK(at100["stage_durations_min"].empty());
    CHECK(at200["max_axial_strain_pct"].get<double>() == Approx(8.16));
    REQUIRE(at200["stress_levels"].size() == 2);
    CHECK(at200["stress_levels"][0].get<double>() == Approx(0.4));
    CHECK(at200["stress_levels"][1].get<double>() == Approx(0.7));
    CHECK(at200["stage_durations_min"][1].get<double>() == Approx(1.02 * 200.0));
}

TEST_CASE("the final model's schemes leave out what the diagnosis's runs leave out", "[server][diagnosis]") {
    const auto scheme = user_scheme();
    LabDataset lab;
    lab.curves = {shear_curve(100, 0.05)};
    DiagnoseOptions options;
    options.relative_density = 0.7;  // compaction held at 1 - D_r: not a parameter
    DiagnosisReport report;
    report.effects = {"rolling_resistance"};
    report.parameters = {param("contact_normal_modulus", 1e8), param("friction", 0.5), param("bond_strength", 0.0),
                         param("rolling_friction", 0.0)};

    SECTION("an effect at its off bound, the artefacts absent, the lab's density held") {
        const json out = model_schemes_json(scheme, lab, options, report);
        REQUIRE(out.size() == 1);
        const json& s = out[0]["scheme"];
        CHECK(s["micro"]["rolling_friction"].get<double>() == 0.0);
        CHECK(s["effects"]["seating_error"] == false);
        CHECK(s["effects"]["membrane_compliance"] == false);
        CHECK(s["effects"]["contact_creep_viscosity"] == false);
        CHECK(s["micro"]["crushing_strength_MPa"].get<double>() == 0.0);
        CHECK(s["specimen"]["compaction_friction_ratio"].get<double>() == Approx(0.3));
        CHECK(s["max_particles"] == options.max_particles);
    }
    SECTION("a parameter of the model missing from the report") {
        report.parameters.pop_back();
        CHECK_THROWS_AS(model_schemes_json(scheme, lab, options, report), std::invalid_argument);
    }
    SECTION("an effect the catalog does not know") {
        report.effects.push_back("gremlins");
        CHECK_THROWS_AS(model_schemes_json(scheme, lab, options, report), std::invalid_argument);
    }
}

namespace {

// A finished diagnosis without DEM runs: the service's remote runner answers with `report`.
json run_made_up_diagnosis(TestServer& srv, const DiagnosisReport& report) {
    srv.service().diagnoses.set_remote_runner(
        [report](std::int64_t, const json&, const LabDataset&, DiagnoseObserver&) {
            return triax::io::diagnosis_report_to_json(report);
        });
    const long long ds = srv.post("/datasets?format=csv",
                                  std::string("confining_kPa,axial_strain_pct,q_kPa\n100,0.5,80\n100,1,120\n100,2,150\n"),
                                  "text/csv")
                             .body["id"];
    const auto sub = srv.post("/datasets/" + std::to_string(ds) + "/diagnose",
                              json{{"scheme", json::parse(R"({"name": "tiny", "max_particles": 40})")},
                                   {"max_particles", 30}, {"seed", 5}});
    INFO(sub.text);
    REQUIRE(sub.status == 202);
    const long long id = sub.body["id"];
    srv.events("/diagnoses/" + std::to_string(id) + "/events");  // ends at done or error
    return srv.get("/diagnoses/" + std::to_string(id)).body;
}

}  // namespace

TEST_CASE("a finished diagnosis stores its model's schemes, or its report without them", "[server][e2e][diagnosis]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    DiagnosisReport report;
    report.chosen_effect = "none";
    report.noise.model_nrmse_per_curve = {{"stress_strain@100kPa", 0.03}};  // as a real report has it
    report.parameters = {param("contact_normal_modulus", 1e8), param("friction", 0.42), param("bond_strength", 0.0),
                         param("compaction_friction_ratio", 0.5)};

    SECTION("the schemes, POSTable to /runs") {
        const json d = run_made_up_diagnosis(srv, report);
        REQUIRE(d["status"] == "done");
        const json& schemes = d["report"]["model_schemes"];
        REQUIRE(schemes.size() == 1);
        const json& s = schemes[0]["scheme"];
        CHECK(schemes[0]["confining_kPa"].get<double>() == Approx(100.0));
        CHECK(s["specimen"]["lateral_boundary"] == "grain_pressure");
        CHECK(s["micro"]["friction"].get<double>() == 0.42);
        CHECK(s["max_particles"] == 30);
        CHECK(s["seed"] == 5);
        const auto run = srv.post("/runs", json{{"scheme", s}});
        INFO(run.text);
        CHECK((run.status == 201 || run.status == 202));
        // The field as schema/openapi.json describes it.
        const json doc = srv.get("/openapi.json").body;
        const json& item = doc["paths"]["/diagnoses/{id}"]["get"]["responses"]["200"]["content"]["application/json"]
                              ["schema"]["properties"]["report"]["properties"]["model_schemes"]["items"];
        for (const auto& [k, v] : schemes[0].items()) CHECK(item["properties"].contains(k));
        CHECK(item["properties"]["scheme"]["$ref"] == "#/components/schemas/Scheme");
    }
    SECTION("a report whose parameters do not fit the model is stored without them") {
        report.parameters.pop_back();
        const json d = run_made_up_diagnosis(srv, report);
        CHECK(d["status"] == "done");
        REQUIRE(d["report"].is_object());
        CHECK(!d["report"].contains("model_schemes"));
    }
}
