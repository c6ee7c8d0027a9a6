// Diagnosis jobs share the bounded queue with runs: a diagnosis waiting behind a held run
// can be listed, followed and cancelled, and its stream ends with the cancellation. (The
// loop itself is tested in tests/diagnose; a real diagnosis needs many DEM runs.)
#include "service_fixture.hpp"

using namespace triax::test;

TEST_CASE("a queued diagnosis is stored, listed, cancelled and its stream ends", "[server][e2e][diagnosis]") {
    ScriptControl control;
    control.hold = true;
    TestServer srv(scripted_executor(control), {}, 1, 4);
    const long long run = srv.post("/runs", json{{"scheme", json::object()}}).body["id"];
    srv.wait_status(run, "running");
    const long long ds = srv.post("/datasets?format=csv",
                                  std::string("confining_kPa,axial_strain_pct,q_kPa\n100,0.5,80\n100,1,120\n100,2,150\n"),
                                  "text/csv")
                             .body["id"];
    const auto sub = srv.post("/datasets/" + std::to_string(ds) + "/diagnose",
                              json{{"scheme_id", 1}, {"budget_runs", 8}, {"seed", 3}});
    REQUIRE(sub.status == 202);
    const long long id = sub.body["id"];
    const auto st = srv.get("/diagnoses/" + std::to_string(id)).body;
    CHECK(st["status"] == "queued");
    CHECK(st["dataset_id"] == ds);
    CHECK(st["report"].is_null());
    CHECK(srv.get("/diagnoses").body["diagnoses"].size() == 1);

    CHECK(srv.post("/diagnoses/" + std::to_string(id) + "/cancel", std::string()).status == 202);
    CHECK(srv.get("/diagnoses/" + std::to_string(id)).body["status"] == "cancelled");
    const auto ev = srv.events("/diagnoses/" + std::to_string(id) + "/events");
    REQUIRE(ev.size() == 2);
    CHECK(ev[0].data["status"] == "queued");
    CHECK(ev[1].type == "error");
    CHECK(ev[1].data["status"] == "cancelled");
    check_problem(srv.post("/diagnoses/" + std::to_string(id) + "/cancel", std::string()), 409);
    control.hold = false;
}

TEST_CASE("finite_difference_uncertainty is read from the diagnose body, type-checked and echoed", "[server][e2e][diagnosis]") {
    ScriptControl control;
    control.hold = true;  // a held run keeps the diagnoses queued: only the request is tested here
    TestServer srv(scripted_executor(control), {}, 1, 8);
    const long long run = srv.post("/runs", json{{"scheme", json::object()}}).body["id"];
    srv.wait_status(run, "running");
    const long long ds = srv.post("/datasets?format=csv", std::string("confining_kPa,axial_strain_pct,q_kPa\n100,0.5,80\n"),
                                  "text/csv")
                             .body["id"];
    const std::string path = "/datasets/" + std::to_string(ds) + "/diagnose";
    for (const json& bad : {json("false"), json(0), json(nullptr), json::array({true})}) {
        INFO(bad.dump());
        const auto r = srv.post(path, json{{"scheme_id", 1}, {"finite_difference_uncertainty", bad}});
        check_problem(r, 422);
        CHECK(r.body["field"] == "/finite_difference_uncertainty");
        CHECK(r.body["detail"].get<std::string>().find("true or false") != std::string::npos);
    }
    CHECK(srv.get("/diagnoses").body["total"] == 0);  // nothing queued by a refused request

    const auto off = srv.post(path, json{{"scheme_id", 1}, {"finite_difference_uncertainty", false}, {"budget_runs", 6}});
    REQUIRE(off.status == 202);
    const auto dflt = srv.post(path, json{{"scheme_id", 1}});
    REQUIRE(dflt.status == 202);
    const auto got_off = srv.get("/diagnoses/" + std::to_string(off.body["id"].get<long long>())).body["options"];
    const auto got_dflt = srv.get("/diagnoses/" + std::to_string(dflt.body["id"].get<long long>())).body["options"];
    CHECK(got_off["finite_difference_uncertainty"] == false);
    CHECK(got_off["budget_runs"] == 6);
    CHECK(got_dflt["finite_difference_uncertainty"] == true);  // the engine's default
    CHECK(got_dflt["budget_runs"] == 12);
    // Concurrency not given: the default, within the machine's threads, recorded as used.
    CHECK(got_dflt["concurrency"].get<int>() >= 1);
    CHECK(got_dflt["concurrency"].get<int>() <= 2);
    for (const auto& id : {off.body["id"], dflt.body["id"]})
        REQUIRE(srv.post("/diagnoses/" + std::to_string(id.get<long long>()) + "/cancel", std::string()).status == 202);
    control.hold = false;
}
