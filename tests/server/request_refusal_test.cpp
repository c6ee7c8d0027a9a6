// Requests the service refuses before any handler runs its logic: multipart bodies (415
// naming what is taken), paths with empty or dot segments (404), diagnose options that do
// not exist (422 naming the field); and what a 500 looks like: logged with a request id,
// the body carrying the id and none of the exception's text.
#include "service_fixture.hpp"

#include <cstdio>
#include <fcntl.h>
#include <fstream>
#include <sstream>

using namespace triax::test;

namespace {

const std::string kCsv = "confining_kPa,axial_strain_pct,q_kPa\n100,0.5,80\n100,1,120\n";

// What the calling thread's code writes to stderr while `fn` runs.
template <class F> std::string capture_stderr(F fn) {
    const auto path = std::filesystem::temp_directory_path() / ("triaxd-stderr-" + std::to_string(getpid()));
    std::fflush(stderr);
    const int saved = dup(2);
    const int file = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    dup2(file, 2);
    close(file);
    fn();
    std::fflush(stderr);
    dup2(saved, 2);
    close(saved);
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    std::filesystem::remove(path);
    return text.str();
}

}  // namespace

TEST_CASE("multipart/form-data is 415 on every POST route, naming the accepted types", "[server][guard][refusal]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const std::string boundary = "XyZ";
    const std::string form = "--XyZ\r\nContent-Disposition: form-data; name=\"file\"; filename=\"a.csv\"\r\n"
                             "Content-Type: text/csv\r\n\r\n" + kCsv + "\r\n--XyZ--\r\n";
    const std::string type = "multipart/form-data; boundary=" + boundary;
    const std::string out = capture_stderr([&] {
        for (const std::string& path : {"/datasets", "/packings", "/schemes", "/runs", "/comparisons", "/estimate",
                                        "/ensembles", "/datasets/1/diagnose", "/runs/1/cancel"}) {
            INFO(path);
            const auto r = srv.post(path, form, type.c_str());
            check_problem(r, 415);
            CHECK(r.body["detail"].get<std::string>().find("application/json") != std::string::npos);
            CHECK(r.body["detail"].get<std::string>().find("text/csv") != std::string::npos);
        }
    });
    CHECK(out.find("500") == std::string::npos);
    CHECK(srv.get("/datasets").body["total"] == 0);
    CHECK(srv.get("/health").status == 200);
}

TEST_CASE("a 500 is logged with a request id and its body carries only the id", "[server][guard][refusal]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    REQUIRE(srv.post("/datasets?format=csv", kCsv, "text/csv").status == 201);
    // A stored column that no longer parses: the listing fails inside the handler.
    srv.service().db.with([](triax::service::Database& db) { db.exec("UPDATE datasets SET header_json = '{broken'"); });
    Reply r;
    const std::string log = capture_stderr([&] { r = srv.get("/datasets"); });
    check_problem(r, 500);
    const std::string id = r.body.value("request_id", "");
    REQUIRE(id.size() == 16);
    CHECK(r.body["detail"].get<std::string>().find(id) != std::string::npos);
    CHECK(r.text.find("parse") == std::string::npos);       // nothing of the parser's message
    CHECK(r.text.find("json.exception") == std::string::npos);
    INFO(log);
    CHECK(log.find("500 request " + id + ": GET /datasets: ") != std::string::npos);
    CHECK(log.find("parse") != std::string::npos);  // the operator gets the cause
}

TEST_CASE("paths with dot or empty segments are 404, the npm tree stays hidden", "[server][guard][refusal]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    for (const std::string& path :
         {"/static/./package.json", "//node_modules/uplot/package.json", "/static//package.json", "/./package.json",
          "/static/../package.json", "/static/./index.html", "//runs", "/runs/./1", "/static/.", "//"}) {
        INFO(path);
        CHECK(srv.raw_status("GET", path) == 404);
    }
    CHECK(srv.raw_status("GET", "/static/index.html") == 200);
    CHECK(srv.raw_status("GET", "/") == 200);
    CHECK(srv.raw_status("GET", "/runs") == 200);
}

TEST_CASE("an unknown diagnose option is 422 naming it, not silently ignored", "[server][guard][refusal]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const auto ds = srv.post("/datasets?format=csv", kCsv, "text/csv");
    REQUIRE(ds.status == 201);
    REQUIRE(srv.post("/schemes", json::object()).status == 201);
    const std::string base = "/datasets/" + std::to_string(ds.body["id"].get<long long>());
    for (const std::string& route : {base + "/diagnose", base + "/diagnosis-plan"}) {
        INFO(route);
        auto r = srv.post(route, json{{"scheme_id", 1}, {"budget_run", 8}});
        check_problem(r, 422);
        CHECK(r.body["field"] == "/budget_run");
        CHECK(r.body["detail"].get<std::string>().find("budget_runs") != std::string::npos);  // the known ones listed
        r = srv.post(route, json{{"scheme_id", 1}, {"a/b", 1}});
        check_problem(r, 422);
        CHECK(r.body["field"] == "/a~1b");
    }
    CHECK(srv.get("/diagnoses").body["total"] == 0);
}
