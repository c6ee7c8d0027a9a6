// Load test of triaxd on loopback, bounded in time: the service in-process (engine
// executor, temporary data directory), one finished run to query, one long run executing,
// then for --seconds: --clients keep-alive clients looping over the result routes, --streams
// SSE streams following the executing run, and one /health probe every 50 ms.
// Reports p50/p99/max latency and errors per class. Never run by CI.
//   load_test [--clients 50] [--seconds 60] [--streams 200]
#include "server/runs/engine_executor.hpp"
#include "server/service.hpp"

#include <httplib.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

using nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

struct Samples {
    std::mutex m;
    std::vector<double> ms;
    long errors = 0;
    void add(double v) {
        std::lock_guard l(m);
        ms.push_back(v);
    }
    void error() {
        std::lock_guard l(m);
        ++errors;
    }
    void report(const char* name) {
        std::lock_guard l(m);
        std::sort(ms.begin(), ms.end());
        auto q = [&](double p) { return ms.empty() ? 0.0 : ms[std::min(ms.size() - 1, static_cast<std::size_t>(p * ms.size()))]; };
        std::printf("%-16s n=%8zu errors=%5ld p50=%8.2f ms p99=%8.2f ms max=%8.2f ms\n", name, ms.size(), errors, q(0.5),
                    q(0.99), ms.empty() ? 0.0 : ms.back());
    }
};

// A small run (about 3 s) and a long one (a creep stage of 1e5 min on the same specimen).
json scheme(bool long_run) {
    json s = json::parse(R"({
      "name": "load", "seed": 11, "max_particles": 40,
      "specimen": {"diameter_mm": 40, "height_mm": 80},
      "gradation": {"kind": "radius_ratio", "r_min_mm": 2, "radius_ratio": 2},
      "micro": {"membrane_particle_radius_mm": 4},
      "loading": {"confining_pressure_kPa": 100, "stress_levels": [], "stage_durations_min": [],
                  "max_axial_strain_pct": 1}})");
    if (long_run) {
        s["loading"]["stress_levels"] = {0.5};
        s["loading"]["stage_durations_min"] = {1.0e5};
    }
    return s;
}

}  // namespace

int main(int argc, char** argv) {
    int clients = 50, seconds = 60, streams = 200;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i];
        const int v = std::stoi(argv[i + 1]);
        if (a == "--clients") clients = v;
        else if (a == "--seconds") seconds = v;
        else if (a == "--streams") streams = v;
    }
    std::mt19937_64 rng(std::random_device{}());
    const auto dir = std::filesystem::temp_directory_path() / ("triaxd-load-" + std::to_string(rng()));
    triax::service::ServiceConfig cfg;
    cfg.port = 0;
    cfg.data_dir = dir / "data";
    cfg.workers = 2;
    cfg.max_threads_per_run = 1;
    int port = 0;
    {
        triax::service::Service service(cfg, triax::service::make_engine_executor());
        port = service.start_background();
        httplib::Client setup("127.0.0.1", port);
        setup.set_read_timeout(120, 0);
        auto post = [&](const json& body) {
            auto r = setup.Post("/runs", body.dump(), "application/json");
            return json::parse(r->body)["id"].get<long long>();
        };
        const long long done = post(json{{"scheme", scheme(false)}});
        for (int i = 0; i < 6000; ++i) {
            auto r = setup.Get(("/runs/" + std::to_string(done)).c_str());
            if (json::parse(r->body)["status"] == "done") break;
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        const long long running = post(json{{"scheme", scheme(true)}});
        std::printf("load_test: port %d, finished run %lld, executing run %lld, %d clients x %d s, %d streams\n", port,
                    done, running, clients, seconds, streams);

        const std::vector<std::string> routes = {
            "/runs/" + std::to_string(done) + "/results/summary",
            "/runs/" + std::to_string(done) + "/results/stress-strain",
            "/runs/" + std::to_string(done) + "/results/stress-strain?max_points=100",
            "/runs/" + std::to_string(done) + "/results/energies",
            "/runs/" + std::to_string(running) + "/results/creep",
            "/runs/" + std::to_string(done),
            "/runs?limit=20",
        };
        Samples results, health, stream_open;
        std::atomic<bool> stop{false};
        std::atomic<int> streams_open{0};
        const auto end = Clock::now() + std::chrono::seconds(seconds);
        std::vector<std::thread> threads;
        for (int s = 0; s < streams; ++s)
            threads.emplace_back([&] {
                httplib::Client c("127.0.0.1", port);
                c.set_read_timeout(5, 0);
                const auto t0 = Clock::now();
                bool first = true;
                auto r = c.Get(("/runs/" + std::to_string(running) + "/events").c_str(), [&](const char*, size_t) {
                    if (first) {
                        stream_open.add(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
                        ++streams_open;
                        first = false;
                    }
                    return !stop.load();
                });
                if (first || (r && r->status != 200)) stream_open.error();
            });
        for (int k = 0; k < clients; ++k)
            threads.emplace_back([&, k] {
                httplib::Client c("127.0.0.1", port);
                c.set_keep_alive(true);
                c.set_read_timeout(10, 0);
                for (std::size_t i = static_cast<std::size_t>(k); Clock::now() < end; ++i) {
                    const auto t0 = Clock::now();
                    auto r = c.Get(routes[i % routes.size()].c_str());
                    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
                    if (!r || r->status != 200) results.error();
                    else results.add(ms);
                }
            });
        threads.emplace_back([&] {
            httplib::Client c("127.0.0.1", port);
            c.set_read_timeout(10, 0);
            while (Clock::now() < end) {
                const auto t0 = Clock::now();
                auto r = c.Get("/health");
                const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
                if (!r || r->status != 200) health.error();
                else health.add(ms);
                std::this_thread::sleep_for(std::chrono::milliseconds(50));
            }
        });
        std::this_thread::sleep_until(end);
        const int open_at_end = streams_open.load();
        stop = true;
        setup.Post(("/runs/" + std::to_string(running) + "/cancel").c_str(), "", "application/json");
        for (auto& t : threads) t.join();
        std::printf("streams open during the test: %d of %d\n", open_at_end, streams);
        results.report("result routes");
        health.report("/health");
        stream_open.report("stream first byte");
        service.stop();
    }
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
    return 0;
}
