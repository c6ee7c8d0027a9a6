// Job lifecycle under cancel and stop: a cancel is honoured within a second in every stage
// of the real engine (generation, consolidation, creep), a cancelled run keeps the stage it
// stopped in, and a stopping service gives every open stream its terminal event.
#include "server/runs/engine_executor.hpp"
#include "service_fixture.hpp"

using namespace triax::test;

namespace {

// Reduced specimen of kill9_test.cpp with one long creep stage.
json small_creep_scheme() {
    return json::parse(R"({
      "name": "lifecycle", "seed": 11, "max_particles": 40,
      "specimen": {"diameter_mm": 40, "height_mm": 80},
      "gradation": {"kind": "radius_ratio", "r_min_mm": 2, "radius_ratio": 2},
      "micro": {"membrane_particle_radius_mm": 4},
      "loading": {"confining_pressure_kPa": 100, "stress_levels": [0.5], "stage_durations_min": [100000],
                  "max_axial_strain_pct": 1}})");
}

// Waits until the run's stage starts with `prefix`; returns its status document.
json wait_stage(const TestServer& srv, long long id, const std::string& prefix, int timeout_s = 120) {
    json st;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(timeout_s);
    while (std::chrono::steady_clock::now() < deadline) {
        st = srv.get("/runs/" + std::to_string(id)).body;
        if (st["stage"].is_string() && st["stage"].get<std::string>().rfind(prefix, 0) == 0) return st;
        if (st.value("status", "") != "running" && st.value("status", "") != "queued") break;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    FAIL("run " << id << " never reached stage " << prefix << ": " << st.dump());
    return st;
}

// Cancels and returns the seconds until the run is recorded cancelled.
double cancel_latency_s(const TestServer& srv, long long id) {
    const auto t0 = std::chrono::steady_clock::now();
    REQUIRE(srv.post("/runs/" + std::to_string(id) + "/cancel", json::object()).status == 202);
    srv.wait_status(id, "cancelled", 30000);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

TEST_CASE("cancel is honoured within a second in generation and creep, and the run keeps its stage",
          "[server][lifecycle][engine]") {
    TestServer srv(triax::service::make_engine_executor());
    // Generation of about 65,000 grains (the placement alone takes minutes): cancelled in it.
    json big = json::parse(R"({"name": "big", "gradation": {"kind": "radius_ratio", "r_min_mm": 1, "radius_ratio": 2},
                               "loading": {"stress_levels": [], "stage_durations_min": []}})");
    auto r = srv.post("/runs", json{{"scheme", big}});
    REQUIRE(r.status == 202);
    const long long gen = r.body["id"];
    wait_stage(srv, gen, "generation");
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // inside the placement
    CHECK(cancel_latency_s(srv, gen) < 1.0);
    const auto g = srv.get("/runs/" + std::to_string(gen)).body;
    CHECK(g["stage"] == "generation");
    CHECK(g["status"] == "cancelled");

    r = srv.post("/runs", json{{"scheme", small_creep_scheme()}});
    REQUIRE(r.status == 202);
    const long long creep = r.body["id"];
    wait_stage(srv, creep, "creep-1");
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    CHECK(cancel_latency_s(srv, creep) < 1.0);
    const auto c = srv.get("/runs/" + std::to_string(creep)).body;
    CHECK(c["stage"] == "creep-1");
    // Its stream ends with the cancellation, not a done event.
    const auto ev = srv.events("/runs/" + std::to_string(creep) + "/events");
    REQUIRE(!ev.empty());
    CHECK(ev.back().type == "error");
    CHECK(ev.back().data["status"] == "cancelled");
}

TEST_CASE("a stopping service interrupts the run and its open streams receive the terminal event",
          "[server][lifecycle]") {
    ScriptControl control;
    control.hold = true;
    auto srv = std::make_unique<TestServer>(scripted_executor(control));
    const auto r = srv->post("/runs", json{{"scheme", json::object()}});
    REQUIRE(r.status == 202);
    const long long id = r.body["id"];
    srv->wait_status(id, "running");
    std::atomic<std::size_t> received{0};
    std::vector<TestServer::Event> events;
    std::thread follower([&] { events = srv->events("/runs/" + std::to_string(id) + "/events", "", &received); });
    for (int i = 0; i < 400 && received == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    REQUIRE(received > 0);
    srv->stop();  // what SIGTERM does in triaxd (main.cpp)
    follower.join();
    REQUIRE(!events.empty());
    CHECK(events.back().type == "error");
    CHECK(events.back().data["status"] == "interrupted");
}
