// POST /datasets/{id}/diagnosis-plan: the runs and minutes of a diagnosis before it starts,
// from the same body as POST /datasets/{id}/diagnose and without starting anything; and the
// diagnose 202 carrying the same plan.
#include "engine/diagnose/dem_forward_model.hpp"
#include "engine/diagnose/diagnosis.hpp"
#include "server/io/diagnosis_json.hpp"
#include "server/io/scheme_json.hpp"
#include "service_fixture.hpp"

using namespace triax::test;
using namespace triax;

namespace {

// Shear curves at 100 and 200 kPa to 5 % strain, one 60-min creep stage at 100 kPa.
json small_dataset() {
    const json shear_rows = json::array({{0.5, 40}, {1, 70}, {2, 100}, {3.5, 115}, {5, 120}});
    json creep_rows = json::array();
    for (int i = 0; i <= 6; ++i) creep_rows.push_back({10.0 * i, 0.1 + 0.02 * std::log1p(10.0 * i)});
    return {{"name", "plan"},
            {"curves",
             {{{"kind", "shear"}, {"confining_kPa", 100}, {"columns", {"axial_strain_pct", "q_kPa"}}, {"rows", shear_rows}},
              {{"kind", "shear"}, {"confining_kPa", 200}, {"columns", {"axial_strain_pct", "q_kPa"}}, {"rows", shear_rows}},
              {{"kind", "creep"},
               {"stage", 1},
               {"confining_kPa", 100},
               {"stress_level", 0.6},
               {"columns", {"time_min", "axial_deformation_mm"}},
               {"rows", creep_rows}}}}};
}

// The engine's plan for the same dataset, scheme and options, built as a diagnosis builds it.
diagnose::DiagnosisPlan engine_plan(TestServer& srv, long long dataset, const json& options) {
    const auto lab = service::load_dataset(srv.service(), dataset, nullptr);
    const auto scheme = io::scheme_from_json(srv.get("/schemes/1").body["scheme"]);
    const auto o = io::diagnose_options_from_json(options);
    const diagnose::DemForwardModel model(scheme, lab, o.threads_per_run, o.max_particles, nullptr, o.packings_per_run,
                                          o.relative_density);
    return diagnose::plan_diagnosis(lab, model, o);
}

}  // namespace

TEST_CASE("the diagnosis plan states runs and minutes from the engine's plan and starts nothing", "[server][e2e][diagnosis]") {
    ScriptControl control;
    control.hold = true;  // a held run: anything queued by mistake would stay visible
    TestServer srv(scripted_executor(control), {}, 1, 8);
    const long long run = srv.post("/runs", json{{"scheme", json::object()}}).body["id"];
    srv.wait_status(run, "running");
    const auto up = srv.post("/datasets?format=json", small_dataset().dump(), "application/json");
    REQUIRE(up.status == 201);
    const long long ds = up.body["id"];
    const std::string path = "/datasets/" + std::to_string(ds) + "/diagnosis-plan";

    const auto p = srv.post(path, json{{"scheme_id", 1}, {"budget_runs", 8}});
    INFO(p.text);
    REQUIRE(p.status == 200);
    const json& plan = p.body;
    CHECK(plan["model_runs_at_most"] == engine_plan(srv, ds, plan["options"]).model_runs);
    CHECK(plan["engine_runs_per_model_run"] == 2);
    // The options as a diagnosis would record them, defaults and concurrency filled in.
    CHECK(plan["options"]["budget_runs"] == 8);
    CHECK(plan["options"]["refine_runs"] == 3);
    CHECK(plan["options"]["max_particles"] == 200);
    CHECK(plan["options"]["concurrency"].get<int>() >= 1);
    CHECK(plan["options"]["relative_density_percent"].is_null());
    // Low: calibration budget + the noise floor's 2 other packings + 4 base parameters.
    CHECK(plan["model_runs_low"] == 8 + 2 + 4);
    CHECK(plan["model_runs_low"].get<int>() < plan["model_runs_at_most"].get<int>());
    CHECK(plan["grains"].get<long long>() > 0);
    CHECK(plan["grains"].get<long long>() <= 200);
    // One engine run per confining pressure: the creep stage at 100 kPa, each shear 2 %
    // past the lab's last reading (5 %).
    const json& conditions = plan["lab_conditions"];
    REQUIRE(conditions.size() == 2);
    CHECK(conditions[0]["confining_kPa"] == Approx(100.0));
    CHECK(conditions[0]["creep_stages"] == 1);
    CHECK(conditions[1]["confining_kPa"] == Approx(200.0));
    CHECK(conditions[1]["creep_stages"] == 0);
    CHECK(conditions[1]["max_axial_strain_pct"] == Approx(5.1));
    double sum_low = 0.0, sum_high = 0.0;
    for (const auto& c : conditions) {
        const auto& m = c["minutes_per_engine_run"];
        CHECK(m["low"].get<double>() > 0.0);
        CHECK(m["low"].get<double>() <= m["typical"].get<double>());
        CHECK(m["typical"].get<double>() <= m["high"].get<double>());
        sum_low += m["low"].get<double>();
        sum_high += m["high"].get<double>();
    }
    // The creep stage adds its holds to the 100-kPa run.
    CHECK(conditions[0]["minutes_per_engine_run"]["typical"].get<double>() >
          conditions[1]["minutes_per_engine_run"]["typical"].get<double>());
    CHECK(plan["minutes_per_model_run"]["low"] == Approx(sum_low));
    CHECK(plan["minutes_per_model_run"]["high"] == Approx(sum_high));
    // Runs at once: a batch's runs over the evaluation threads.
    const int c = std::min(plan["options"]["concurrency"].get<int>(), plan["options"]["batch_runs"].get<int>());
    const auto rounds = [c](const json& runs) { return std::ceil(runs.get<double>() / c); };
    CHECK(plan["minutes_estimate"]["low"] == Approx(rounds(plan["model_runs_low"]) * sum_low));
    CHECK(plan["minutes_estimate"]["high"] == Approx(rounds(plan["model_runs_at_most"]) * sum_high));
    // Expected: the low runs plus one of max_effects search steps, at the typical minutes.
    const int low = plan["model_runs_low"], most = plan["model_runs_at_most"];
    const int steps = plan["options"]["max_effects"];
    // The lab has shear curves and a creep stage: the kinds' weighing (a refinement of
    // refine_runs and the noise floor's 2 other packings again) is expected in full.
    const int weighing = plan["options"]["refine_runs"].get<int>() + 2;
    CHECK(plan["model_runs_expected"] == low + weighing + (most - low - weighing + steps - 1) / steps);
    CHECK(plan["minutes_estimate"]["expected"] ==
          Approx(rounds(plan["model_runs_expected"]) * plan["minutes_per_model_run"]["typical"].get<double>()));
    CHECK(plan["minutes_estimate"]["low"].get<double>() <= plan["minutes_estimate"]["expected"].get<double>());
    CHECK(plan["minutes_estimate"]["expected"].get<double>() <= plan["minutes_estimate"]["high"].get<double>());

    SECTION("the budget and the packings change it") {
        const auto more = srv.post(path, json{{"scheme_id", 1}, {"budget_runs", 20}}).body;
        CHECK(more["model_runs_at_most"] == plan["model_runs_at_most"].get<int>() + 12);
        CHECK(more["model_runs_at_most"] == engine_plan(srv, ds, more["options"]).model_runs);
        CHECK(more["minutes_estimate"]["high"].get<double>() > plan["minutes_estimate"]["high"].get<double>());
        const auto two = srv.post(path, json{{"scheme_id", 1}, {"budget_runs", 8}, {"packings_per_run", 2}}).body;
        CHECK(two["minutes_per_model_run"]["typical"] == Approx(2 * plan["minutes_per_model_run"]["typical"].get<double>()));
        // A stated relative density holds the compaction friction: one base parameter less.
        const auto held = srv.post(path, json{{"scheme_id", 1}, {"budget_runs", 8}, {"relative_density_percent", 60}}).body;
        CHECK(held["options"]["relative_density_percent"] == Approx(60.0));
        CHECK(held["model_runs_low"] == 8 + 2 + 3);
        CHECK(held["model_runs_at_most"] == engine_plan(srv, ds, held["options"]).model_runs);
    }
    SECTION("an inline scheme is checked as the diagnosis checks it, and not stored") {
        const auto schemes = srv.get("/schemes").body["total"];
        const auto inl = srv.post(path, json{{"scheme", srv.get("/schemes/1").body["scheme"]}, {"budget_runs", 8}});
        REQUIRE(inl.status == 200);
        CHECK(inl.body["model_runs_at_most"] == plan["model_runs_at_most"]);
        CHECK(srv.get("/schemes").body["total"] == schemes);
        const auto bad = srv.post(path, json{{"scheme", {{"micro", {{"friction", -1}}}}}});
        check_problem(bad, 422);
        CHECK(bad.body["field"].get<std::string>().rfind("/scheme/micro/friction", 0) == 0);
    }
    SECTION("a bad option is refused naming the field, as the diagnose route refuses it") {
        for (const auto& route : {path, "/datasets/" + std::to_string(ds) + "/diagnose"}) {
            INFO(route);
            auto r = srv.post(route, json{{"scheme_id", 1}, {"budget_runs", 3}});
            check_problem(r, 422);
            CHECK(r.body["field"] == "/budget_runs");
            r = srv.post(route, json{{"scheme_id", 1}, {"concurrency", 64}, {"threads_per_run", 64}});
            check_problem(r, 422);
            CHECK(r.body["field"] == "/concurrency");
            r = srv.post(route, json{{"budget_runs", 8}});
            check_problem(r, 422);
            CHECK(r.body["field"] == "/scheme");
            check_problem(srv.post(route, json{{"scheme_id", 99}}), 404);
        }
        check_problem(srv.post("/datasets/999/diagnosis-plan", json{{"scheme_id", 1}}), 404);
    }
    SECTION("a dataset no diagnosis can use is 422 with the engine's reason") {
        const long long thin = srv.post("/datasets?format=csv", std::string("confining_kPa,axial_strain_pct,q_kPa\n100,0.5,80\n"),
                                        "text/csv")
                                   .body["id"];
        const auto r = srv.post("/datasets/" + std::to_string(thin) + "/diagnosis-plan", json{{"scheme_id", 1}});
        check_problem(r, 422);
        CHECK(r.body["detail"].get<std::string>().find("no usable curve") != std::string::npos);
    }
    SECTION("the answer is the one schema/openapi.json describes") {
        const auto doc = srv.get("/openapi.json").body;
        const auto& schema = doc["components"]["schemas"]["DiagnosisPlan"];
        const auto keys = [](const json& object) {
            std::set<std::string> out;
            for (const auto& [k, v] : object.items()) out.insert(k);
            return out;
        };
        CHECK(keys(plan) == keys(schema["properties"]));
        CHECK(keys(conditions[0]) == keys(schema["properties"]["lab_conditions"]["items"]["properties"]));
        CHECK(doc["paths"]["/datasets/{id}/diagnosis-plan"]["post"]["responses"]["200"]["content"]["application/json"]["schema"]["$ref"] ==
              "#/components/schemas/DiagnosisPlan");
    }
    CHECK(srv.get("/diagnoses").body["total"] == 0);  // the plan queued nothing
    CHECK(srv.get("/runs").body["total"] == 1);
    control.hold = false;
}

TEST_CASE("the diagnose 202 carries the plan of what it started", "[server][e2e][diagnosis]") {
    ScriptControl control;
    control.hold = true;  // the diagnosis stays queued behind a held run
    TestServer srv(scripted_executor(control), {}, 1, 8);
    const long long run = srv.post("/runs", json{{"scheme", json::object()}}).body["id"];
    srv.wait_status(run, "running");
    const long long ds = srv.post("/datasets?format=json", small_dataset().dump(), "application/json").body["id"];
    const json body{{"scheme_id", 1}, {"budget_runs", 10}, {"seed", 4}};
    const auto plan = srv.post("/datasets/" + std::to_string(ds) + "/diagnosis-plan", body);
    REQUIRE(plan.status == 200);
    const auto sub = srv.post("/datasets/" + std::to_string(ds) + "/diagnose", body);
    INFO(sub.text);
    REQUIRE(sub.status == 202);
    CHECK(sub.body["status"] == "queued");
    CHECK(sub.body["plan"] == plan.body);
    // The options the plan states are the ones the diagnosis records.
    const long long id = sub.body["id"];
    CHECK(srv.get("/diagnoses/" + std::to_string(id)).body["options"] == plan.body["options"]);
    // A dataset the diagnosis cannot use is still accepted (it fails with the engine's
    // reason when it runs), with no plan.
    const long long thin =
        srv.post("/datasets?format=csv", std::string("confining_kPa,axial_strain_pct,q_kPa\n100,0.5,80\n"), "text/csv").body["id"];
    const auto unplanned = srv.post("/datasets/" + std::to_string(thin) + "/diagnose", json{{"scheme_id", 1}});
    REQUIRE(unplanned.status == 202);
    CHECK(unplanned.body["plan"].is_null());
    for (const auto& d : {sub.body["id"], unplanned.body["id"]})
        REQUIRE(srv.post("/diagnoses/" + std::to_string(d.get<long long>()) + "/cancel", std::string()).status == 202);
    control.hold = false;
}
