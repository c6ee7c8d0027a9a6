// Malformed input must be answered with a problem naming the cause, never take the service
// down or store something that later breaks a listing. Found by hand-fuzzing: a CSV with a
// non-UTF-8 byte made the 500 answer itself throw (its detail quoted the byte), which ended
// the process.
#include "server/http/problem.hpp"
#include "service_fixture.hpp"

using namespace triax::test;

TEST_CASE("invalid_utf8_at finds the first byte that is not well-formed UTF-8", "[server][errors]") {
    using triax::service::invalid_utf8_at;
    const auto npos = std::string_view::npos;
    CHECK(invalid_utf8_at("") == npos);
    CHECK(invalid_utf8_at("plain, 100 kPa") == npos);
    CHECK(invalid_utf8_at("\xc3\xa9t\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80") == npos);  // été € 😀
    CHECK(invalid_utf8_at("ab\xff") == 2);                 // never a UTF-8 byte
    CHECK(invalid_utf8_at("a\xc0\xaf") == 1);              // overlong '/'
    CHECK(invalid_utf8_at("x\xed\xa0\x80") == 1);          // UTF-16 surrogate
    CHECK(invalid_utf8_at("12\xe2\x82") == 2);             // truncated at the end
    CHECK(invalid_utf8_at("\xe2(\xa1") == 0);              // continuation byte missing
    CHECK(invalid_utf8_at("\xf4\x90\x80\x80") == 0);       // beyond U+10FFFF
    CHECK(invalid_utf8_at("\x80") == 0);                   // stray continuation byte
}

TEST_CASE("an upload that is not UTF-8 is refused with its position - the service keeps serving", "[server][errors]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const std::string ok = "confining_kPa,axial_strain_pct,q_kPa\n100,0.5,80\n100,1,120\n";
    for (const char* format : {"csv", "gds", "ags", "json"}) {
        INFO(format);
        auto r = srv.post(std::string("/datasets?format=") + format,
                          std::string("kind,confining_kPa,axial_strain_pct,q_kPa\nsh\xff" "ear,100,0.5,80\n"), "text/csv");
        check_problem(r, 422);
        CHECK(r.body["line"] == 2);
        CHECK(r.body["column"] == 3);
        CHECK(r.body["detail"].get<std::string>().find("UTF-8") != std::string::npos);
    }
    // A byte that is not UTF-8 in the first column of the first line.
    auto r = srv.post("/datasets", std::string("\xfe\xff"), "text/csv");
    check_problem(r, 422);
    CHECK(r.body["line"] == 1);
    CHECK(r.body["column"] == 1);
    check_problem(srv.post("/datasets?format=csv&name=%ff%fe", ok, "text/csv"), 400);
    // Nothing was stored, and the service still answers and lists.
    CHECK(srv.get("/health").status == 200);
    const auto list = srv.get("/datasets");
    REQUIRE(list.status == 200);
    CHECK(list.body["datasets"].empty());
    const auto good = srv.post("/datasets?format=csv&name=%C3%A9t%C3%A9", ok, "text/csv");
    REQUIRE(good.status == 201);
    CHECK(good.body["name"] == "\xc3\xa9t\xc3\xa9");
    CHECK(srv.get("/datasets").body["datasets"].size() == 1);
}

TEST_CASE("wrong types, huge numbers and non-JSON numbers are 400/422 naming the cause", "[server][errors]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    check_problem(srv.post("/schemes", std::string("{\"seed\": NaN}")), 400);
    auto r = srv.post("/schemes", std::string("{\"seed\": 1e400}"));
    check_problem(r, 422);  // well-formed JSON, a value beyond a double
    CHECK(r.body["field"] == "/seed");
    r = srv.post("/runs", std::string("{\"scheme_id\": 1e300}"));
    check_problem(r, 422);
    CHECK(r.body["field"] == "/scheme_id");
    r = srv.post("/runs", std::string("{\"scheme_id\": 18446744073709551615}"));
    check_problem(r, 422);
    CHECK(r.body["field"] == "/scheme_id");
    r = srv.post("/comparisons", json{{"run_id", "1"}, {"dataset_id", json::array({1})}});
    check_problem(r, 422);
    CHECK(r.body["field"] == "/run_id");
    r = srv.post("/runs", json::array({1, 2}));
    check_problem(r, 422);
    check_problem(srv.post("/datasets?format=json", std::string("[]"), "application/json"), 422);
    check_problem(srv.post("/datasets?format=gds", std::string("\n\n"), "text/csv"), 422);
    check_problem(srv.post("/datasets?format=ags", std::string("\n\n"), "text/csv"), 422);
    check_problem(srv.post("/datasets?format=csv", std::string("confining_kPa,q_kPa\n"), "text/csv"), 422);
    CHECK(srv.get("/health").status == 200);
}

TEST_CASE("a dataset that would not read back is refused, not stored", "[server][errors]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    // 1e308 kPa is a finite double, but not in Pa: stored it would become null.
    const auto r = srv.post("/datasets?format=json",
                            std::string(R"({"curves":[{"kind":"shear","confining_kPa":1e308,)"
                                        R"("columns":["axial_strain_pct","q_kPa"],"rows":[[1,2],[2,3]]}]})"),
                            "application/json");
    check_problem(r, 422);
    CHECK(r.body["field"].get<std::string>().find("confining_kPa") != std::string::npos);
    CHECK(srv.get("/datasets").body["datasets"].empty());
}
