// Paging of the list endpoints: newest first, `limit` (default 50, at most 500) and the
// cursor `before_id`; rows added while a client pages do not shift its next page.
#include "service_fixture.hpp"

using namespace triax::test;

namespace {
std::vector<long long> ids(const json& items) {
    std::vector<long long> out;
    for (const auto& x : items) out.push_back(x["id"].get<long long>());
    return out;
}
}  // namespace

TEST_CASE("list endpoints page newest first with limit and before_id", "[server][e2e][paging]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const std::string csv = "confining_kPa,axial_strain_pct,q_kPa\n100,0.5,80\n100,1,120\n";
    for (int i = 0; i < 7; ++i) REQUIRE(srv.post("/datasets?format=csv", csv, "text/csv").status == 201);

    auto p1 = srv.get("/datasets?limit=3").body;
    CHECK(ids(p1["datasets"]) == std::vector<long long>{7, 6, 5});
    CHECK(p1["total"] == 7);
    CHECK(p1["limit"] == 3);
    REQUIRE(p1["next_before_id"] == 5);
    // A dataset added between two pages appears on a fresh first page, not on the next one.
    REQUIRE(srv.post("/datasets?format=csv", csv, "text/csv").status == 201);
    auto p2 = srv.get("/datasets?limit=3&before_id=5").body;
    CHECK(ids(p2["datasets"]) == std::vector<long long>{4, 3, 2});
    CHECK(p2["total"] == 8);
    auto p3 = srv.get("/datasets?limit=3&before_id=" + std::to_string(p2["next_before_id"].get<long long>())).body;
    CHECK(ids(p3["datasets"]) == std::vector<long long>{1});
    CHECK(p3["next_before_id"].is_null());
    // Exactly `limit` rows left: no next page is announced.
    CHECK(srv.get("/datasets?limit=8").body["next_before_id"].is_null());
    const auto all = srv.get("/datasets").body;
    CHECK(all["limit"] == 50);
    CHECK(all["datasets"].size() == 8);

    // Every list pages the same way and names the parameter at fault.
    for (const char* list : {"/schemes", "/runs", "/datasets", "/comparisons", "/diagnoses"}) {
        INFO(list);
        const auto ok = srv.get(std::string(list) + "?limit=500");
        REQUIRE(ok.status == 200);
        CHECK(ok.body.contains("total"));
        CHECK(ok.body.contains("next_before_id"));
        auto r = srv.get(std::string(list) + "?limit=501");
        check_problem(r, 422);
        CHECK(r.body["detail"].get<std::string>().find("'limit'") != std::string::npos);
        CHECK(r.body["limit"] == "1 <= limit <= 500");
        check_problem(srv.get(std::string(list) + "?limit=0"), 422);
        check_problem(srv.get(std::string(list) + "?limit=ten"), 400);
        r = srv.get(std::string(list) + "?before_id=0");
        check_problem(r, 422);
        CHECK(r.body["detail"].get<std::string>().find("'before_id'") != std::string::npos);
    }
    // Runs page the same way (three finished runs).
    for (int i = 0; i < 3; ++i) srv.wait_status(srv.post("/runs", json{{"scheme", json::object()}}).body["id"].get<long long>(), "done");
    const auto runs = srv.get("/runs?limit=2").body;
    CHECK(ids(runs["runs"]) == std::vector<long long>{3, 2});
    CHECK(runs["total"] == 3);
    CHECK(ids(srv.get("/runs?limit=2&before_id=2").body["runs"]) == std::vector<long long>{1});
}

TEST_CASE("runs and diagnoses filter by status: the active jobs are one page however long the history",
          "[server][e2e][paging]") {
    ScriptControl control;
    control.shear_points = 5;
    control.creep_stages = 0;
    TestServer srv(scripted_executor(control), {}, 1, 4);
    // 62 finished runs, one held running, one queued behind it, then 55 newer cancelled
    // ones: the two active runs are beyond the first page of /runs.
    for (int i = 0; i < 62; ++i) srv.wait_status(srv.post("/runs", json{{"scheme", json::object()}}).body["id"].get<long long>(), "done");
    control.hold = true;
    const long long active = srv.post("/runs", json{{"scheme_id", 1}}).body["id"];
    srv.wait_status(active, "running");
    const long long waiting = srv.post("/runs", json{{"scheme_id", 1}}).body["id"];
    for (int i = 0; i < 55; ++i) {
        const long long id = srv.post("/runs", json{{"scheme_id", 1}}).body["id"];
        REQUIRE(srv.post("/runs/" + std::to_string(id) + "/cancel", std::string()).status == 202);
    }
    const auto first_page = srv.get("/runs").body;
    CHECK(first_page["total"] == 119);
    for (const auto& r : first_page["runs"]) CHECK(r["id"].get<long long>() > waiting);

    const auto act = srv.get("/runs?status=queued,running").body;
    CHECK(ids(act["runs"]) == std::vector<long long>{waiting, active});
    CHECK(act["total"] == 2);
    CHECK(act["next_before_id"].is_null());
    const auto done = srv.get("/runs?status=done&limit=50").body;
    CHECK(done["total"] == 62);
    CHECK(done["runs"].size() == 50);
    for (const auto& r : done["runs"]) CHECK(r["status"] == "done");
    // The cursor pages inside the filter.
    const auto done2 = srv.get("/runs?status=done&limit=50&before_id=" + std::to_string(done["next_before_id"].get<long long>())).body;
    CHECK(done2["runs"].size() == 12);
    CHECK(done2["next_before_id"].is_null());
    CHECK(srv.get("/runs?status=cancelled,cancelled").body["total"] == 55);

    // Diagnoses filter the same way (one queued behind the held run, one cancelled).
    const long long ds = srv.post("/datasets?format=csv", std::string("confining_kPa,axial_strain_pct,q_kPa\n100,0.5,80\n"), "text/csv").body["id"];
    const long long d1 = srv.post("/datasets/" + std::to_string(ds) + "/diagnose", json{{"scheme_id", 1}}).body["id"];
    const long long d2 = srv.post("/datasets/" + std::to_string(ds) + "/diagnose", json{{"scheme_id", 1}}).body["id"];
    REQUIRE(srv.post("/diagnoses/" + std::to_string(d1) + "/cancel", std::string()).status == 202);
    const auto diag = srv.get("/diagnoses?status=queued,running").body;
    CHECK(ids(diag["diagnoses"]) == std::vector<long long>{d2});
    CHECK(diag["total"] == 1);
    CHECK(srv.get("/diagnoses?status=cancelled").body["total"] == 1);
    REQUIRE(srv.post("/diagnoses/" + std::to_string(d2) + "/cancel", std::string()).status == 202);

    for (const char* bad : {"/runs?status=finished", "/runs?status=queued,", "/diagnoses?status=DONE"}) {
        INFO(bad);
        const auto r = srv.get(bad);
        check_problem(r, 422);
        CHECK(r.body["detail"].get<std::string>().find("'status'") != std::string::npos);
    }
    // Lists without a status column ignore the parameter, as any unknown one.
    CHECK(srv.get("/datasets?status=done").body["total"] == 1);
    REQUIRE(srv.post("/runs/" + std::to_string(waiting) + "/cancel", std::string()).status == 202);
    REQUIRE(srv.post("/runs/" + std::to_string(active) + "/cancel", std::string()).status == 202);
    control.hold = false;
}
