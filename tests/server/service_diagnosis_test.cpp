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
