#pragma once
// In-process triaxd on an ephemeral loopback port with a temporary data directory, and a
// small HTTP/SSE client. The scripted executor stands in for the engine in the tests of
// the service's own mechanics (queue, cancel, replay, restart, comparisons with a known
// answer); engine_run_test.cpp runs the real engine.
#include "server/service.hpp"

#include <catch2/catch.hpp>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <random>
#include <set>
#include <thread>

namespace triax::test {

using nlohmann::json;

inline std::filesystem::path make_temp_dir(const std::string& tag) {
    std::mt19937_64 rng(std::random_device{}());
    auto p = std::filesystem::temp_directory_path() / ("triaxd-" + tag + "-" + std::to_string(rng()));
    std::filesystem::create_directories(p);
    return p;
}

// The scripted model: q(e) = 300 (1 - exp(-e / 2)) kPa with e in %, creep deformation of
// stage k = 0.1 k + 0.05 ln(1 + t) mm with t in minutes.
inline double script_q_kpa(double strain_pct) { return 300.0 * (1.0 - std::exp(-strain_pct / 2.0)); }
inline double script_creep_mm(int stage, double t_min) { return 0.1 * stage + 0.05 * std::log1p(t_min); }

struct ScriptControl {
    std::atomic<bool> hold{false};      // executor waits (polling cancel) while true
    std::atomic<int> started{0};
    std::atomic<bool> fail{false};      // throw a simulation error mid-run
    int shear_points = 200;
    int creep_stages = 2;
    int creep_points = 40;
};

inline service::RunExecutor scripted_executor(ScriptControl& control) {
    return [&control](const json& scheme, service::RunContext& ctx) -> json {
        ++control.started;
        while (control.hold) {
            if (ctx.cancel_requested()) throw service::RunCancelled();
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        const double sigma3 = scheme["loading"].value("confining_pressure_kPa", 100.0);
        json ss = json::array(), vol = json::array(), creep = json::array(), en = json::array(), ms = json::array();
        ctx.emit("stage", {{"stage", "shear"}, {"index", 0}});
        for (int i = 0; i < control.shear_points; ++i) {
            if (ctx.cancel_requested()) throw service::RunCancelled();
            if (control.fail && i == 10) throw std::runtime_error("kinetic energy exploded at step 1234");
            const double e = 10.0 * i / (control.shear_points - 1);
            const double q = script_q_kpa(e), ev = 0.5 * std::sin(e / 3.0);
            ss.push_back({e, q, sigma3 + q / 3.0, sigma3 + q, sigma3});
            vol.push_back({e, ev});
            ctx.emit("shear", {{"axial_strain_pct", e}, {"q_kPa", q}, {"p_kPa", sigma3 + q / 3.0},
                               {"sigma1_kPa", sigma3 + q}, {"sigma3_kPa", sigma3}, {"volumetric_strain_pct", ev}});
            if (i % 50 == 0)
                ctx.emit("progress", {{"stage", "shear"}, {"progress_pct", 50.0 * i / control.shear_points}, {"eta_s", 1.0}});
        }
        for (int k = 1; k <= control.creep_stages; ++k) {
            ctx.emit("stage", {{"stage", "creep-" + std::to_string(k)}, {"index", k}, {"stress_level", 0.2 * k},
                               {"q_target_kPa", 60.0 * k}});
            for (int i = 0; i < control.creep_points; ++i) {
                const double t = 240.0 * i / (control.creep_points - 1);
                const double d = script_creep_mm(k, t);
                creep.push_back({k, t, d, d / 2.0});
                ctx.emit("creep", {{"stage", k}, {"time_min", t}, {"axial_deformation_mm", d}, {"axial_strain_pct", d / 2.0}});
            }
            en.push_back({1 + k, 100 * k, 240.0, 1.0, 2.0, 3.0, 0.0, 0.5, 7.0, 0.1 * k});
            ms.push_back({2, 100 * k, 240.0, 0.1, 0.0, 0.0, 0.0, 0.36, 4.2});
        }
        return {{"summary", {{"sigma3_kPa", sigma3}, {"q_failure_kPa", script_q_kpa(10.0)}, {"particle_count", 321}}},
                {"series", {{"stress_strain", ss}, {"volumetric", vol}, {"creep", creep}, {"energies", en},
                            {"measurements", ms}}}};
    };
}

// A TCP connection to 127.0.0.1:port with receive and send timeouts (s; 0 = none).
inline int connect_loopback(int port, int timeout_s = 10) {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    REQUIRE(fd >= 0);
    if (timeout_s > 0) {
        timeval tv{timeout_s, 0};
        setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
        setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
    }
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    REQUIRE(connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0);
    return fd;
}

struct Reply {
    int status = 0;
    json body;
    std::string text, content_type;
};

class TestServer {
public:
    // `tweak` adjusts the configuration (limits, token) before the service starts.
    explicit TestServer(service::RunExecutor executor, std::filesystem::path dir = {}, int workers = 1,
                        int queue_limit = 8, const std::function<void(service::ServiceConfig&)>& tweak = {})
        : dir_(dir.empty() ? make_temp_dir("srv") : dir), owns_dir_(dir.empty()) {
        service::ServiceConfig cfg;
        cfg.host = "127.0.0.1";
        cfg.port = 0;
        cfg.data_dir = dir_ / "data";
        cfg.workers = workers;
        cfg.queue_limit = queue_limit;
        cfg.max_body_bytes = 1 << 20;
        cfg.http_threads = 24;
        cfg.max_event_streams = 16;
        if (tweak) tweak(cfg);
        service_ = std::make_unique<service::Service>(cfg, std::move(executor));
        port_ = service_->start_background();
    }
    ~TestServer() {
        stop();
        if (owns_dir_) {
            std::error_code ec;
            std::filesystem::remove_all(dir_, ec);
        }
    }
    void stop() {
        if (service_) service_->stop();
        service_.reset();
    }
    service::Service& service() { return *service_; }
    const std::filesystem::path& dir() const { return dir_; }
    int port() const { return port_; }

    httplib::Client client() const {
        httplib::Client c("127.0.0.1", port_);
        c.set_read_timeout(60, 0);
        return c;
    }
    Reply get(const std::string& path) const { return wrap(client().Get(path.c_str())); }
    Reply del(const std::string& path) const { return wrap(client().Delete(path.c_str())); }
    Reply post(const std::string& path, const std::string& body, const char* type = "application/json") const {
        return wrap(client().Post(path.c_str(), body, type));
    }
    Reply post(const std::string& path, const json& body) const { return post(path, body.dump()); }
    // A POST with no body and neither Content-Length nor Transfer-Encoding (what
    // `curl -X POST URL` sends), over a raw socket; gives up after 3 s without an answer.
    Reply post_without_length(const std::string& path) const {
        const int fd = connect_loopback(port_, 3);
        const std::string request = "POST " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
        REQUIRE(send(fd, request.data(), request.size(), 0) == static_cast<ssize_t>(request.size()));
        std::string raw;
        char buf[4096];
        for (ssize_t n; (n = recv(fd, buf, sizeof buf, 0)) > 0;) raw.append(buf, static_cast<std::size_t>(n));
        close(fd);
        INFO("raw answer to body-less POST " << path << ": '" << raw << "'");
        const auto head_end = raw.find("\r\n\r\n");
        REQUIRE(raw.rfind("HTTP/1.1 ", 0) == 0);
        REQUIRE(head_end != std::string::npos);
        Reply out;
        out.status = std::stoi(raw.substr(9, 3));
        out.text = raw.substr(head_end + 4);
        const auto ct = raw.find("Content-Type: ");
        if (ct != std::string::npos && ct < head_end)
            out.content_type = raw.substr(ct + 14, raw.find("\r\n", ct) - ct - 14);
        if (out.content_type.find("json") != std::string::npos && !out.text.empty()) out.body = json::parse(out.text);
        return out;
    }

    // A request with exactly the header lines given (none added but Content-Length and
    // Connection: close), over a raw socket; the answer's status and raw text.
    std::pair<int, std::string> raw(const std::string& method, const std::string& path,
                                    const std::vector<std::string>& lines, const std::string& body = "") const {
        const int fd = connect_loopback(port_, 10);
        std::string request = method + " " + path + " HTTP/1.1\r\n";
        for (const auto& l : lines) request += l + "\r\n";
        request += "Content-Length: " + std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body;
        send(fd, request.data(), request.size(), MSG_NOSIGNAL);
        std::string answer;
        char buf[4096];
        for (ssize_t n; (n = recv(fd, buf, sizeof buf, 0)) > 0;) answer.append(buf, static_cast<std::size_t>(n));
        close(fd);
        INFO(method << " " << path << " answered: " << answer);
        REQUIRE(answer.rfind("HTTP/1.1 ", 0) == 0);
        return {std::stoi(answer.substr(9, 3)), answer};
    }
    // The status of raw(...) with "Host: 127.0.0.1:PORT" first.
    int raw_status(const std::string& method, const std::string& path, std::vector<std::string> lines = {},
                   const std::string& body = "") const {
        lines.insert(lines.begin(), "Host: 127.0.0.1:" + std::to_string(port_));
        return raw(method, path, lines, body).first;
    }

    struct Event {
        long long id = 0;
        std::string type;
        json data;
    };
    // Reads an SSE stream until the server closes it. `received` (optional) counts the bytes
    // read so far, so another thread can wait until the stream is open instead of sleeping.
    std::vector<Event> events(const std::string& path, const std::string& last_event_id = "",
                              std::atomic<std::size_t>* received = nullptr) const {
        auto c = client();
        std::string buffer;
        httplib::Headers headers;
        if (!last_event_id.empty()) headers.emplace("Last-Event-ID", last_event_id);
        auto res = c.Get(path.c_str(), headers, [&](const char* data, size_t n) {
            buffer.append(data, n);
            if (received) *received += n;
            return true;
        });
        REQUIRE(res);
        REQUIRE(res->status == 200);
        std::vector<Event> out;
        std::size_t pos = 0;
        while (true) {
            const auto end = buffer.find("\n\n", pos);
            if (end == std::string::npos) break;
            const std::string block = buffer.substr(pos, end - pos);
            pos = end + 2;
            Event e;
            std::size_t lp = 0;
            bool any = false;
            while (lp < block.size()) {
                auto le = block.find('\n', lp);
                if (le == std::string::npos) le = block.size();
                const std::string line = block.substr(lp, le - lp);
                lp = le + 1;
                if (line.rfind("id: ", 0) == 0) { e.id = std::stoll(line.substr(4)); any = true; }
                else if (line.rfind("event: ", 0) == 0) e.type = line.substr(7);
                else if (line.rfind("data: ", 0) == 0) e.data = json::parse(line.substr(6));
            }
            if (any) out.push_back(std::move(e));
        }
        return out;
    }

    json wait_status(long long run_id, const std::string& status, int timeout_ms = 60000) const {
        json last;
        for (int i = 0; i < timeout_ms / 5; ++i) {
            last = get("/runs/" + std::to_string(run_id)).body;
            if (last.value("status", "") == status) return last;
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        FAIL("run " << run_id << " did not reach " << status << ", last: " << last.dump());
        return last;
    }

private:
    static Reply wrap(const httplib::Result& r) {
        REQUIRE(r);
        Reply out;
        out.status = r->status;
        out.text = r->body;
        out.content_type = r->get_header_value("Content-Type");
        if (out.content_type.find("json") != std::string::npos && !r->body.empty()) out.body = json::parse(r->body);
        return out;
    }
    std::filesystem::path dir_;
    bool owns_dir_ = false;
    std::unique_ptr<service::Service> service_;
    int port_ = 0;
};

// A problem-details answer with the given status.
inline void check_problem(const Reply& r, int status) {
    INFO(r.text);
    CHECK(r.status == status);
    CHECK(r.content_type == "application/problem+json");
    CHECK(r.body.value("status", 0) == status);
    CHECK_FALSE(r.body.value("detail", std::string()).empty());
}

}  // namespace triax::test
