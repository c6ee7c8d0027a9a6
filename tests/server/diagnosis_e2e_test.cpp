// A real diagnosis through the service over loopback: a tiny specimen (about 40 particles,
// coarse membrane, 1 % axial strain, no creep), the smallest budget the request allows and
// the parameters' uncertainty from the regression over the runs made
// (finite_difference_uncertainty false: no extra Jacobian runs). POST
// /datasets/{id}/diagnose, follow its stream to the end, GET the stored report with the
// calibrated model's scheme (POSTed to /runs), restart on the same data directory and read
// the same report back. It costs six tiny DEM runs, about
// 7 s alone. The scheme is chosen so that every run's consolidation meets its criterion:
// with radius ratio 1.5, or with the default contact modulus (230 MPa, which the calibration
// varies up to x5), this specimen's consolidation ends at the protocol's 400,000-step cap
// with the platen stress 5-11 % off sigma3, about 17 s per run (the test took 57 s alone,
// 236 s under load, then 78 s with ratio 2 alone).
#include "service_fixture.hpp"

using namespace triax::test;

TEST_CASE("a real diagnosis runs through the service and its report survives a restart", "[server][e2e][diagnosis][engine][slow]") {
    const auto dir = make_temp_dir("diag");
    ScriptControl control;  // runs are not used; the diagnosis drives the engine itself
    const json scheme = json::parse(R"({
      "name": "tiny", "seed": 11, "max_particles": 40,
      "specimen": {"diameter_mm": 40, "height_mm": 80},
      "gradation": {"kind": "radius_ratio", "r_min_mm": 2, "radius_ratio": 2},
      "micro": {"membrane_particle_radius_mm": 4, "normal_modulus_MPa": 60, "shear_modulus_MPa": 40},
      "loading": {"confining_pressure_kPa": 100, "stress_levels": [], "stage_durations_min": [],
                  "max_axial_strain_pct": 1}})");
    long long id = 0;
    std::string report_text;
    {
        TestServer srv(scripted_executor(control), dir);
        const long long ds = srv.post("/datasets?format=csv",
                                      std::string("confining_kPa,axial_strain_pct,q_kPa\n100,0.1,20\n100,0.3,50\n"
                                                  "100,0.5,70\n100,0.8,90\n"),
                                      "text/csv")
                                 .body["id"];
        const auto sub = srv.post("/datasets/" + std::to_string(ds) + "/diagnose",
                                  json{{"scheme", scheme}, {"budget_runs", 4}, {"refine_runs", 1}, {"max_candidates", 1},
                                       {"max_effects", 1}, {"seed", 1}, {"max_particles", 40},
                                       {"finite_difference_uncertainty", false}});
        INFO(sub.text);
        REQUIRE(sub.status == 202);
        id = sub.body["id"];
        // The stream ends by itself at done (or error): follow it to the end.
        const auto ev = srv.events("/diagnoses/" + std::to_string(id) + "/events");
        REQUIRE(!ev.empty());
        INFO(ev.back().data.dump());
        CHECK(ev.back().type == "done");
        CHECK(std::any_of(ev.begin(), ev.end(), [](const auto& e) { return e.type == "progress"; }));
        for (std::size_t i = 1; i < ev.size(); ++i) CHECK(ev[i].id == ev[i - 1].id + 1);
        const auto got = srv.get("/diagnoses/" + std::to_string(id));
        REQUIRE(got.body["status"] == "done");
        CHECK(got.body["progress_pct"] == 100.0);
        const json& report = got.body["report"];
        REQUIRE(report.is_object());
        CHECK(report["chosen_effect"].is_string());
        CHECK(!report["parameters"].empty());
        CHECK(!report["error_before"].empty());
        CHECK(report["verdict"].is_string());
        CHECK(got.body["options"]["finite_difference_uncertainty"] == false);
        CHECK(report["runs_used"].get<int>() >= 4);  // at least the calibration budget
        // The calibrated model's scheme (one lab condition): the diagnosis's DEM model, not
        // the scheme diagnosed, and a run accepts it as it is.
        REQUIRE(report["model_schemes"].size() == 1);
        const json& model = report["model_schemes"][0]["scheme"];
        CHECK(model["specimen"]["lateral_boundary"] == "grain_pressure");
        CHECK(model["max_particles"] == 40);
        const auto friction = std::find_if(report["parameters"].begin(), report["parameters"].end(),
                                           [](const json& p) { return p["name"] == "friction"; });
        REQUIRE(friction != report["parameters"].end());
        CHECK(model["micro"]["friction"] == (*friction)["value"]);
        const auto run = srv.post("/runs", json{{"scheme", model}});
        INFO(run.text);
        CHECK((run.status == 201 || run.status == 202));
        report_text = report.dump();
    }
    {
        TestServer srv(scripted_executor(control), dir);
        const auto again = srv.get("/diagnoses/" + std::to_string(id));
        CHECK(again.body["status"] == "done");
        CHECK(again.body["report"].dump() == report_text);
        CHECK(srv.get("/diagnoses").body["diagnoses"].size() == 1);
    }
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
}
