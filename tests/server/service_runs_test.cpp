// Runs over loopback with the scripted executor: submit, follow the stream to the end,
// query the results, replay with Last-Event-ID, queue limit, cancel, re-run, failures.
#include "service_fixture.hpp"

using namespace triax::test;

TEST_CASE("submit a run, follow its stream to the end, query its results", "[server][e2e]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const auto sub = srv.post("/runs", json{{"scheme", {{"name", "tiny"}}}});
    REQUIRE(sub.status == 202);
    const long long id = sub.body["id"];
    CHECK(sub.body["status"] == "queued");

    const auto events = srv.events("/runs/" + std::to_string(id) + "/events");
    REQUIRE(events.size() > 10);
    for (std::size_t i = 0; i < events.size(); ++i) CHECK(events[i].id == static_cast<long long>(i + 1));
    CHECK(events.front().type == "status");
    CHECK(events.front().data["status"] == "queued");
    CHECK(events[1].data["status"] == "running");
    CHECK(events.back().type == "done");
    std::size_t shear = 0, creep = 0;
    for (const auto& e : events) {
        shear += e.type == "shear";
        creep += e.type == "creep";
    }
    CHECK(shear == 200);
    CHECK(creep == 80);

    const auto st = srv.get("/runs/" + std::to_string(id)).body;
    CHECK(st["status"] == "done");
    CHECK(st["progress_pct"] == 100.0);
    CHECK(st["name"] == "tiny");
    CHECK_FALSE(st["finished_at"].is_null());

    const auto base = "/runs/" + std::to_string(id) + "/results/";
    const auto summary = srv.get(base + "summary");
    REQUIRE(summary.status == 200);
    CHECK(summary.body["particle_count"] == 321);

    const auto ss = srv.get(base + "stress-strain?max_points=5").body;
    CHECK(ss["columns"] == json({"axial_strain_pct", "q_kPa", "p_kPa", "sigma1_kPa", "sigma3_kPa"}));
    REQUIRE(ss["rows"].size() == 5);
    CHECK(ss["rows"][0][0] == 0.0);
    CHECK(ss["rows"][4][0] == 10.0);  // first and last kept
    CHECK(ss["rows"][4][1].get<double>() == Approx(script_q_kpa(10.0)));

    const auto ranged = srv.get(base + "stress-strain?from=2&to=4").body["rows"];
    REQUIRE_FALSE(ranged.empty());
    for (const auto& r : ranged) CHECK((r[0] >= 2.0 && r[0] <= 4.0));

    const auto c2 = srv.get(base + "creep?stage=2").body;
    CHECK(c2["columns"] == json({"time_min", "axial_deformation_mm", "axial_strain_pct"}));
    CHECK(c2["rows"].size() == 40);
    CHECK(c2["rows"][0][1].get<double>() == Approx(0.2));
    CHECK(srv.get(base + "creep").body["rows"].size() == 80);
    CHECK(srv.get(base + "volumetric").body["rows"].size() == 200);
    CHECK(srv.get(base + "energies").body["rows"].size() == 2);
    CHECK(srv.get(base + "measurements").body["columns"][0] == "sphere");

    const auto csv = srv.get(base + "creep?stage=1&format=csv");
    CHECK(csv.content_type == "text/csv");
    CHECK(csv.text.rfind("time_min,axial_deformation_mm,axial_strain_pct\n", 0) == 0);

    const auto list = srv.get("/runs").body["runs"];
    REQUIRE(list.size() == 1);
    CHECK(list[0]["id"] == id);
}

TEST_CASE("Last-Event-ID replays only what was missed - late clients get the whole history", "[server][e2e]") {
    ScriptControl control;
    control.shear_points = 20;
    TestServer srv(scripted_executor(control));
    const long long id = srv.post("/runs", json{{"scheme", json::object()}}).body["id"];
    // A late client: the run has ended, so its whole history is stored and a stream that
    // ends short (the client's read timeout on a loaded machine) cannot pass for it.
    srv.wait_status(id, "done");
    const auto all = srv.events("/runs/" + std::to_string(id) + "/events");
    REQUIRE(all.size() > 12);
    REQUIRE(all.back().type == "done");
    const auto tail = srv.events("/runs/" + std::to_string(id) + "/events", "10");
    REQUIRE(tail.size() == all.size() - 10);
    CHECK(tail.front().id == 11);
    CHECK(tail.back().type == "done");
    const auto by_query = srv.events("/runs/" + std::to_string(id) + "/events?last_event_id=" + std::to_string(all.size() - 1));
    REQUIRE(by_query.size() == 1);
    CHECK(by_query[0].type == "done");
    // Reconnecting after the end (as EventSource does) gives an empty stream that closes.
    CHECK(srv.events("/runs/" + std::to_string(id) + "/events", std::to_string(all.size())).empty());
}

TEST_CASE("a client connected while the run is held receives the events as they happen", "[server][e2e]") {
    ScriptControl control;
    control.hold = true;
    control.shear_points = 30;
    TestServer srv(scripted_executor(control));
    const long long id = srv.post("/runs", json{{"scheme", json::object()}}).body["id"];
    std::vector<TestServer::Event> got;
    std::atomic<std::size_t> received{0};
    std::thread reader([&] { got = srv.events("/runs/" + std::to_string(id) + "/events", "", &received); });
    srv.wait_status(id, "running");
    // The reader has the stored history (queued, running) and now waits on the live stream.
    const auto open_by = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (received == 0 && std::chrono::steady_clock::now() < open_by) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    REQUIRE(received > 0);
    control.hold = false;
    reader.join();
    REQUIRE_FALSE(got.empty());
    CHECK(got.back().type == "done");
}

TEST_CASE("queue limit answers 429 - cancel queued and running runs - re-run", "[server][e2e]") {
    ScriptControl control;
    control.hold = true;
    TestServer srv(scripted_executor(control), {}, 1, 1);
    const long long a = srv.post("/runs", json{{"scheme", json::object()}}).body["id"];
    for (int i = 0; i < 20000 && control.started == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    srv.wait_status(a, "running");
    const auto b = srv.post("/runs", json{{"scheme_id", 1}});
    REQUIRE(b.status == 202);
    const auto full = srv.post("/runs", json{{"scheme_id", 1}});
    check_problem(full, 429);
    CHECK(full.body["limit"] == "queue_limit = 1");
    CHECK(srv.get("/runs").body["runs"].size() == 2);  // the refused run left nothing

    const long long bid = b.body["id"];
    CHECK(srv.post("/runs/" + std::to_string(bid) + "/cancel", std::string()).status == 202);
    CHECK(srv.get("/runs/" + std::to_string(bid)).body["status"] == "cancelled");
    check_problem(srv.post("/runs/" + std::to_string(bid) + "/cancel", std::string()), 409);

    CHECK(srv.post("/runs/" + std::to_string(a) + "/cancel", std::string()).status == 202);
    srv.wait_status(a, "cancelled");
    const auto ev = srv.events("/runs/" + std::to_string(a) + "/events");
    CHECK(ev.back().type == "error");
    CHECK(ev.back().data["status"] == "cancelled");

    control.hold = false;
    const auto again = srv.post("/runs/" + std::to_string(a) + "/rerun", std::string());
    REQUIRE(again.status == 202);
    const long long c = again.body["id"];
    CHECK(c != a);
    srv.wait_status(c, "done");
    CHECK(srv.get("/runs/" + std::to_string(c)).body["rerun_of"] == a);
}

TEST_CASE("an engine error fails the run with its message, streamed and stored", "[server][e2e]") {
    ScriptControl control;
    control.fail = true;
    TestServer srv(scripted_executor(control));
    const long long id = srv.post("/runs", json{{"scheme", json::object()}}).body["id"];
    const auto ev = srv.events("/runs/" + std::to_string(id) + "/events");
    CHECK(ev.back().type == "error");
    CHECK(ev.back().data["status"] == "failed");
    const auto st = srv.get("/runs/" + std::to_string(id)).body;
    CHECK(st["status"] == "failed");
    CHECK_THAT(st["error"].get<std::string>(), Catch::Contains("kinetic energy exploded"));
    // Partial series stay readable from the events; the summary does not exist.
    CHECK(srv.get("/runs/" + std::to_string(id) + "/results/stress-strain").body["rows"].size() == 10);
    check_problem(srv.get("/runs/" + std::to_string(id) + "/results/summary"), 409);
}
