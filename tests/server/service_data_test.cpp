// Datasets, comparisons with a known answer, restart (graceful and after a crash), the
// error path of every endpoint, and the OpenAPI description against the served routes.
#include "service_fixture.hpp"

#include "server/store/database.hpp"

#include <fstream>
#include <set>

using namespace triax::test;

namespace {

// Lab readings = scripted model + 5 kPa on q, and exactly the model on creep stage 2.
std::string offset_dataset_csv() {
    std::string csv = "kind,stage,confining_kPa,time_min,axial_strain_pct,axial_deformation_mm,q_kPa\n";
    for (int i = 0; i <= 16; ++i) {
        const double e = 0.3 + 0.6 * i;
        csv += "shear,0,100,," + std::to_string(e) + ",," + std::to_string(script_q_kpa(e) + 5.0) + "\n";
    }
    for (int i = 0; i <= 8; ++i) {
        const double t = 1.0 + 29.0 * i;
        csv += "creep,2,100," + std::to_string(t) + ",," + std::to_string(script_creep_mm(2, t)) + ",120\n";
    }
    csv += "creep,3,100,1,,0.5,150\ncreep,3,100,2,,0.6,150\n";  // a stage the run does not have
    return csv;
}

long long finished_run(TestServer& srv) {
    const long long id = srv.post("/runs", json{{"scheme", json::object()}}).body["id"];
    srv.wait_status(id, "done");
    return id;
}

}  // namespace

TEST_CASE("upload a dataset, compare with a run: metrics match the known offset", "[server][e2e]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const auto run = finished_run(srv);
    const auto up = srv.post("/datasets?name=offset&format=csv", offset_dataset_csv(), "text/csv");
    REQUIRE(up.status == 201);
    CHECK(up.body["name"] == "offset");
    REQUIRE(up.body["curves"].size() == 3);
    CHECK(up.body["curves"][0]["points"] == 17);
    const long long ds = up.body["id"];

    const auto cmp = srv.post("/comparisons", json{{"run_id", run}, {"dataset_id", ds}});
    REQUIRE(cmp.status == 201);
    REQUIRE(cmp.body["curves"].size() == 2);
    const auto& q = cmp.body["curves"][0];
    CHECK(q["curve"] == "stress_strain");
    CHECK(q["unit"] == "kPa");
    CHECK(q["n"] == 17);
    // Linear interpolation of a 200-point model: error far below the 5 kPa offset.
    CHECK(q["rmse"].get<double>() == Approx(5.0).margin(0.05));
    CHECK(q["max_error"].get<double>() == Approx(5.0).margin(0.1));
    CHECK(q["residual"][0][3].get<double>() == Approx(-5.0).margin(0.1));  // model - lab
    const auto& c = cmp.body["curves"][1];
    CHECK(c["curve"] == "creep");
    CHECK(c["stage"] == 2);
    CHECK(c["unit"] == "mm");
    CHECK(c["rmse"].get<double>() < 0.01);
    REQUIRE(cmp.body["skipped"].size() == 1);
    CHECK(cmp.body["skipped"][0]["stage"] == 3);

    const long long cid = cmp.body["id"];
    const auto again = srv.get("/comparisons/" + std::to_string(cid)).body;
    CHECK(again["curves"][0]["rmse"] == q["rmse"]);
    CHECK(srv.get("/comparisons").body["comparisons"].size() == 1);
    CHECK(srv.get("/datasets/" + std::to_string(ds)).body["data"]["curves"].size() == 3);

    // JSON and GDS uploads take the same path.
    const auto js = srv.post("/datasets", json{{"name", "j"}, {"curves", {{{"kind", "shear"}, {"confining_kPa", 100},
                                                 {"columns", {"axial_strain_pct", "q_kPa"}}, {"rows", {{1, 80}, {2, 130}}}}}}});
    CHECK(js.status == 201);
    CHECK(js.body["format"] == "json");
    CHECK(srv.del("/datasets/" + std::to_string(ds)).status == 204);
    check_problem(srv.get("/comparisons/" + std::to_string(cid)), 404);  // cascaded
}

TEST_CASE("restart: everything stored is found again - unfinished runs become interrupted", "[server][e2e]") {
    const auto dir = make_temp_dir("restart");
    ScriptControl control;
    long long done_run = 0, held_run = 0, ds = 0, cmp = 0;
    {
        TestServer srv(scripted_executor(control), dir);
        done_run = finished_run(srv);
        ds = srv.post("/datasets?format=csv", offset_dataset_csv(), "text/csv").body["id"];
        cmp = srv.post("/comparisons", json{{"run_id", done_run}, {"dataset_id", ds}}).body["id"];
        control.hold = true;
        held_run = srv.post("/runs", json{{"scheme_id", 1}}).body["id"];
        srv.wait_status(held_run, "running");
        srv.stop();  // graceful stop while a run is in progress
    }
    control.hold = false;
    {
        TestServer srv(scripted_executor(control), dir);
        CHECK(srv.get("/runs/" + std::to_string(done_run)).body["status"] == "done");
        CHECK(srv.get("/runs/" + std::to_string(done_run) + "/results/stress-strain").body["rows"].size() == 200);
        CHECK(srv.get("/runs/" + std::to_string(held_run)).body["status"] == "interrupted");
        const auto ev = srv.events("/runs/" + std::to_string(held_run) + "/events");
        CHECK(ev.back().data["status"] == "interrupted");
        CHECK(srv.get("/datasets/" + std::to_string(ds)).status == 200);
        CHECK(srv.get("/comparisons/" + std::to_string(cmp)).body["curves"].size() == 2);
        CHECK(srv.get("/schemes").body["schemes"].size() >= 1);
        const auto re = srv.post("/runs/" + std::to_string(held_run) + "/rerun", std::string());
        REQUIRE(re.status == 202);
        srv.wait_status(re.body["id"].get<long long>(), "done");
    }
    // A crash (kill -9) leaves the row "running": the next start marks it interrupted.
    {
        triax::service::Database db(dir / "data" / "triax.db", std::filesystem::path(TRIAX_SOURCE_DIR) / "schema" / "migrations");
        db.exec("INSERT INTO runs(scheme_id, name, status, created_at) VALUES (1, 'crashed', 'running', 'now')");
    }
    {
        TestServer srv(scripted_executor(control), dir);
        const auto runs = srv.get("/runs").body["runs"];
        CHECK(runs[0]["name"] == "crashed");
        CHECK(runs[0]["status"] == "interrupted");
    }
    std::filesystem::remove_all(dir);
}

TEST_CASE("a full disk refuses new data with 507 and keeps what was stored", "[server][store]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const auto run = finished_run(srv);
    const long long ds = srv.post("/datasets?format=csv", offset_dataset_csv(), "text/csv").body["id"];
    // Cap the database at its current size: the next write fails as on a full disk.
    srv.service().db.with([](triax::service::Database& db) {
        auto st = db.prepare("PRAGMA page_count");
        st.step();
        db.exec("PRAGMA max_page_count = " + std::to_string(st.int64(0)));
    });
    std::string big = offset_dataset_csv();
    for (int i = 0; i < 200; ++i) big += "shear,0,100,," + std::to_string(20.0 + i) + ",,100\n";
    const auto full = srv.post("/datasets?format=csv", big, "text/csv");
    check_problem(full, 507);
    CHECK(srv.get("/datasets/" + std::to_string(ds)).status == 200);
    CHECK(srv.get("/runs/" + std::to_string(run) + "/results/stress-strain").body["rows"].size() == 200);
    CHECK(srv.get("/datasets").body["datasets"].size() == 1);
}

TEST_CASE("error path of every endpoint answers problem details", "[server][errors]") {
    ScriptControl control;
    control.hold = true;
    TestServer srv(scripted_executor(control));
    // service
    check_problem(srv.get("/no/such/route"), 404);
    // schemes
    check_problem(srv.post("/schemes", std::string("{not json")), 400);
    auto r = srv.post("/schemes", json{{"specimen", {{"target_porosity", 1.5}}}});
    check_problem(r, 422);
    CHECK(r.body["field"] == "/specimen/target_porosity");
    // Beyond the engine's own specimen budget: refused naming the gradation field.
    r = srv.post("/schemes", json{{"gradation", {{"kind", "radius_ratio"}, {"r_min_mm", 0.001}, {"radius_ratio", 1.01}}}});
    check_problem(r, 422);
    CHECK(r.body["field"] == "/gradation/r_min_mm");
    // Within it (about 960,000 grains) but beyond this service's particle limit.
    r = srv.post("/schemes", json{{"gradation", {{"kind", "radius_ratio"}, {"r_min_mm", 0.5}, {"radius_ratio", 1.5}}}});
    check_problem(r, 422);
    CHECK(r.body["limit"].get<std::string>().find("particle_count") != std::string::npos);
    r = srv.post("/schemes", json{{"gradation", {{"kind", "radius_ratio"}, {"r_min_mm", -1}}}});
    check_problem(r, 422);
    CHECK(r.body["field"].get<std::string>().rfind("/gradation", 0) == 0);
    check_problem(srv.get("/schemes/999"), 404);
    check_problem(srv.get("/schemes/abc"), 404);
    // runs
    check_problem(srv.post("/runs", json::object()), 422);
    r = srv.post("/runs", json{{"scheme_id", 999}});
    check_problem(r, 404);
    r = srv.post("/runs", json{{"scheme", json::object()}, {"threads", 100000}});
    check_problem(r, 422);
    CHECK(r.body["field"] == "/threads");
    r = srv.post("/runs", json{{"scheme", json::object()}, {"bogus", 1}});
    check_problem(r, 422);
    CHECK(r.body["field"] == "/bogus");
    r = srv.post("/runs", json{{"scheme", {{"specimen", {{"diameter_mm", -1}}}}}});
    check_problem(r, 422);
    CHECK(r.body["field"].get<std::string>().rfind("/scheme/specimen", 0) == 0);
    check_problem(srv.get("/runs/999"), 404);
    check_problem(srv.post("/runs/999/cancel", std::string()), 404);
    check_problem(srv.post("/runs/999/rerun", std::string()), 404);
    check_problem(srv.get("/runs/999/events"), 404);
    const long long held = srv.post("/runs", json{{"scheme", json::object()}}).body["id"];
    srv.wait_status(held, "running");
    check_problem(srv.post("/runs/" + std::to_string(held) + "/rerun", std::string()), 409);
    check_problem(srv.get("/runs/" + std::to_string(held) + "/events?last_event_id=x"), 400);
    // results
    check_problem(srv.get("/runs/999/results/summary"), 404);
    check_problem(srv.get("/runs/" + std::to_string(held) + "/results/summary"), 409);
    check_problem(srv.get("/runs/999/results/stress-strain"), 404);
    check_problem(srv.get("/runs/" + std::to_string(held) + "/results/volumetric?max_points=0"), 422);
    check_problem(srv.get("/runs/" + std::to_string(held) + "/results/creep?stage=0"), 422);
    check_problem(srv.get("/runs/" + std::to_string(held) + "/results/energies?from=abc"), 400);
    check_problem(srv.get("/runs/" + std::to_string(held) + "/results/measurements?format=xml"), 400);
    check_problem(srv.get("/runs/" + std::to_string(held) + "/results/stress-strain?from=5&to=1"), 422);
    // datasets
    check_problem(srv.post("/datasets", std::string(), "text/csv"), 400);
    check_problem(srv.post("/datasets?format=xls", std::string("a"), "text/csv"), 400);
    r = srv.post("/datasets?format=csv", std::string("confining_kPa,q_kPa,axial_strain_pct\n100,1,2\n100,zz,3\n"), "text/csv");
    check_problem(r, 422);
    CHECK(r.body["line"] == 3);
    CHECK(r.body["column"] == 5);
    r = srv.post("/datasets?format=json", std::string("{\"curves\":[{\"kind\":\"nope\"}]}"), "application/json");
    check_problem(r, 422);
    CHECK(r.body["field"] == "/curves/0/kind");
    check_problem(srv.get("/datasets/999"), 404);
    check_problem(srv.del("/datasets/999"), 404);
    // comparisons
    check_problem(srv.post("/comparisons", json{{"run_id", held}}), 422);
    check_problem(srv.post("/comparisons", json{{"run_id", 999}, {"dataset_id", 1}}), 404);
    const long long ds = srv.post("/datasets?format=csv", offset_dataset_csv(), "text/csv").body["id"];
    check_problem(srv.post("/comparisons", json{{"run_id", held}, {"dataset_id", ds}}), 409);
    check_problem(srv.get("/comparisons/999"), 404);
    // diagnoses
    check_problem(srv.post("/datasets/999/diagnose", json{{"scheme", json::object()}}), 404);
    r = srv.post("/datasets/" + std::to_string(ds) + "/diagnose", json{{"scheme", json::object()}, {"budget_runs", -3}});
    check_problem(r, 422);
    CHECK(r.body["field"] == "/budget_runs");
    check_problem(srv.post("/datasets/" + std::to_string(ds) + "/diagnose", json{{"budget_runs", 8}}), 422);
    r = srv.post("/datasets/" + std::to_string(ds) + "/diagnose", json{{"scheme_id", 1}, {"concurrency", 64}, {"threads_per_run", 64}});
    check_problem(r, 422);
    CHECK(r.body["field"] == "/concurrency");
    check_problem(srv.get("/diagnoses/999"), 404);
    check_problem(srv.post("/diagnoses/999/cancel", std::string()), 404);
    check_problem(srv.get("/diagnoses/999/events"), 404);
    // size limit (1 MiB in the fixture)
    check_problem(srv.post("/datasets?format=csv", std::string(2 << 20, 'x'), "text/csv"), 413);
    control.hold = false;
}

TEST_CASE("the OpenAPI description and the served routes agree", "[server][openapi]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    std::ifstream in(std::filesystem::path(TRIAX_SOURCE_DIR) / "schema" / "openapi.json");
    const auto doc = json::parse(in);
    CHECK(srv.get("/openapi.json").body == doc);
    CHECK(doc["openapi"].get<std::string>().rfind("3.", 0) == 0);
    std::set<std::pair<std::string, std::string>> described, served;
    for (const auto& [path, item] : doc["paths"].items())
        for (const auto& [method, op] : item.items()) {
            std::string m = method;
            for (auto& ch : m) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
            described.insert({m, path});
        }
    for (const auto& r : srv.service().routes) served.insert(r);
    served.insert({"GET", "/"});  // the web page, served from the mounted web directory
    CHECK(described == served);
    // The page itself is there.
    const auto page = srv.get("/");
    CHECK(page.status == 200);
    CHECK(page.content_type.find("text/html") != std::string::npos);
}
