// Body-less POSTs (cancel, rerun) sent without Content-Length, as `curl -X POST URL` does:
// the service treats the body as empty (RFC 9112 6.3) instead of waiting for one and
// answering 400.
#include "service_fixture.hpp"

using namespace triax::test;

TEST_CASE("cancel and rerun accept a POST without body or Content-Length", "[server][e2e]") {
    ScriptControl control;
    control.hold = true;
    TestServer srv(scripted_executor(control), {}, 1, 4);
    const long long run = srv.post("/runs", json{{"scheme", json::object()}}).body["id"];
    srv.wait_status(run, "running");
    const long long ds = srv.post("/datasets?format=csv",
                                  std::string("confining_kPa,axial_strain_pct,q_kPa\n100,0.5,80\n100,1,120\n"), "text/csv")
                             .body["id"];
    const auto diag = srv.post("/datasets/" + std::to_string(ds) + "/diagnose", json{{"scheme_id", 1}, {"budget_runs", 8}});
    REQUIRE(diag.status == 202);
    const long long diag_id = diag.body["id"];

    const auto dc = srv.post_without_length("/diagnoses/" + std::to_string(diag_id) + "/cancel");
    INFO(dc.text);
    CHECK(dc.status == 202);
    CHECK(srv.get("/diagnoses/" + std::to_string(diag_id)).body["status"] == "cancelled");

    const auto rc = srv.post_without_length("/runs/" + std::to_string(run) + "/cancel");
    INFO(rc.text);
    CHECK(rc.status == 202);
    CHECK(rc.body["status"] == "cancelling");
    srv.wait_status(run, "cancelled");

    control.hold = false;
    const auto again = srv.post_without_length("/runs/" + std::to_string(run) + "/rerun");
    INFO(again.text);
    REQUIRE(again.status == 202);
    srv.wait_status(again.body["id"].get<long long>(), "done");

    // The usual answers still come through: an unknown run is 404, a finished one 409.
    check_problem(srv.post_without_length("/runs/999/cancel"), 404);
    check_problem(srv.post_without_length("/runs/" + std::to_string(run) + "/cancel"), 409);
    // A POST that needs a body and has none is refused for its content, not for its framing.
    check_problem(srv.post_without_length("/schemes"), 400);
}
