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
