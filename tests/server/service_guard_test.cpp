// The service under hostile clients: chunked bodies over the cap, streams that would hold
// every HTTP thread, other sites (Origin, Host, content type), the optional token, wrong
// methods and paths with NUL bytes. Each case fails against a service without the guard.
#include "service_fixture.hpp"

#include <cstdio>
#include <future>

using namespace triax::test;

namespace {

// Sends `total` bytes of CSV as a chunked POST and returns the status line's code (0 if
// the server answered nothing).
int post_chunked(int port, const std::string& path, std::size_t total) {
    const int fd = connect_loopback(port);
    std::string head = "POST " + path + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) +
                       "\r\nContent-Type: text/csv\r\nTransfer-Encoding: chunked\r\nConnection: close\r\n\r\n";
    send(fd, head.data(), head.size(), MSG_NOSIGNAL);
    std::string body = "confining_kPa,axial_strain_pct,q_kPa\n";
    while (body.size() < total) body += "100,0.5,80\n";
    for (std::size_t at = 0; at < body.size(); at += 64 * 1024) {
        const std::string chunk = body.substr(at, 64 * 1024);
        char size_line[32];
        std::snprintf(size_line, sizeof size_line, "%zx\r\n", chunk.size());
        const std::string piece = size_line + chunk + "\r\n";
        if (send(fd, piece.data(), piece.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(piece.size())) break;
    }
    send(fd, "0\r\n\r\n", 5, MSG_NOSIGNAL);
    std::string raw;
    char buf[4096];
    for (ssize_t n; (n = recv(fd, buf, sizeof buf, 0)) > 0;) raw.append(buf, static_cast<std::size_t>(n));
    close(fd);
    return raw.rfind("HTTP/1.1 ", 0) == 0 ? std::stoi(raw.substr(9, 3)) : 0;
}

Reply request(const TestServer& srv, const std::string& method, const std::string& path, const httplib::Headers& headers,
              const std::string& body = "", const char* type = "application/json") {
    auto c = srv.client();
    httplib::Result r = method == "GET"    ? c.Get(path.c_str(), headers)
                        : method == "POST" ? c.Post(path.c_str(), headers, body, type)
                        : method == "PUT"  ? c.Put(path.c_str(), headers, body, type)
                        : method == "PATCH" ? c.Patch(path.c_str(), headers, body, type)
                                            : c.Delete(path.c_str(), headers);
    REQUIRE(r);
    Reply out;
    out.status = r->status;
    out.text = r->body;
    out.content_type = r->get_header_value("Content-Type");
    if (out.content_type.find("json") != std::string::npos && !r->body.empty()) out.body = json::parse(r->body);
    out.text += "\nAllow: " + r->get_header_value("Allow") + "\nSet-Cookie: " + r->get_header_value("Set-Cookie");
    return out;
}

}  // namespace

TEST_CASE("a chunked body over the size limit is 413 and nothing is stored", "[server][guard]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));  // 1 MiB limit
    CHECK(post_chunked(srv.port(), "/datasets?format=csv", 256 * 1024) == 201);
    CHECK(post_chunked(srv.port(), "/datasets?format=csv", 3u << 20) == 413);
    CHECK(post_chunked(srv.port(), "/no/such/route", 3u << 20) == 413);
    CHECK(srv.get("/datasets").body["total"] == 1);
    CHECK(srv.get("/health").status == 200);
}

TEST_CASE("the listen backlog is at least 128", "[server][guard]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    // ss shows a listening socket's backlog as its Send-Q.
    const std::string cmd = "ss -ltnH 'sport = :" + std::to_string(srv.port()) + "' 2>/dev/null";
    FILE* p = popen(cmd.c_str(), "r");
    REQUIRE(p);
    char line[512] = {0};
    const bool got = std::fgets(line, sizeof line, p) != nullptr;
    pclose(p);
    REQUIRE(got);  // ss comes with iproute2 (scripts/install-deps.sh)
    char state[32];
    long recv_q = 0, send_q = 0;
    REQUIRE(std::sscanf(line, "%31s %ld %ld", state, &recv_q, &send_q) == 3);
    CHECK(send_q >= 128);
}

TEST_CASE("event streams are capped with 503 and never starve /health or the result routes", "[server][guard]") {
    ScriptControl control;
    control.hold = true;
    TestServer srv(scripted_executor(control), {}, 1, 8, [](triax::service::ServiceConfig& c) {
        c.http_threads = 12;
        c.max_event_streams = 4;
    });
    const auto run = srv.post("/runs", json{{"scheme", json::object()}});
    REQUIRE(run.status == 202);
    const std::string events = "/runs/" + std::to_string(run.body["id"].get<long long>()) + "/events";
    // Twelve browser tabs following the run: four streams, the rest refused at once.
    std::vector<std::future<int>> tabs;
    for (int i = 0; i < 12; ++i)
        tabs.push_back(std::async(std::launch::async, [&] {
            auto c = srv.client();
            auto r = c.Get(events.c_str(), [](const char*, size_t) { return true; });
            return r ? r->status : -1;
        }));
    for (int i = 0; i < 400 && srv.service().event_streams.open() < 4; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    CHECK(srv.service().event_streams.open() == 4);
    int refused = 0;
    for (auto& t : tabs)
        if (t.wait_for(std::chrono::seconds(5)) == std::future_status::ready) refused += t.get() == 503 ? 1 : 0;
    CHECK(refused == 8);
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < 20; ++i) {
        CHECK(srv.get("/health").status == 200);
        CHECK(srv.get("/runs").status == 200);
    }
    CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::seconds(2));
    control.hold = false;  // the run ends: the four streams get their terminal event and close
    srv.wait_status(run.body["id"].get<long long>(), "done");
    for (int i = 0; i < 400 && srv.service().event_streams.open() > 0; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    CHECK(srv.service().event_streams.open() == 0);
}

TEST_CASE("JSON endpoints take application/json only (415)", "[server][guard]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    for (const char* path : {"/schemes", "/runs", "/comparisons"}) {
        INFO(path);
        check_problem(srv.post(path, "{}", "text/plain"), 415);
        check_problem(srv.post(path, "{}", "application/x-www-form-urlencoded"), 415);
    }
    CHECK(srv.post("/schemes", "{}", "application/json; charset=utf-8").status == 201);
    CHECK(srv.get("/schemes").body["total"] == 1);
}

TEST_CASE("Host and Origin must be this service's: other sites and DNS rebinding are 403", "[server][guard]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const std::string port = std::to_string(srv.port());
    check_problem(request(srv, "GET", "/runs", {{"Host", "attacker.example:" + port}}), 403);
    check_problem(request(srv, "GET", "/runs", {{"Host", "127.0.0.1:1"}}), 403);
    check_problem(request(srv, "POST", "/schemes", {{"Origin", "http://attacker.example"}}, "{}"), 403);
    check_problem(request(srv, "POST", "/schemes", {{"Origin", "null"}}, "{}"), 403);
    check_problem(request(srv, "DELETE", "/datasets/1", {{"Origin", "http://attacker.example:" + port}}), 403);
    CHECK(request(srv, "GET", "/runs", {{"Host", "localhost:" + port}}).status == 200);
    CHECK(request(srv, "POST", "/schemes", {{"Origin", "http://127.0.0.1:" + port}}, "{}").status == 201);
    CHECK(request(srv, "POST", "/schemes", {{"Origin", "http://localhost:" + port}}, "{}").status == 201);
    CHECK(srv.get("/schemes").body["total"] == 2);
}

TEST_CASE("with a token every route but /health needs it, the page gets it as a strict cookie", "[server][guard]") {
    ScriptControl control;
    const std::string token = "s3cret-token-0123456789";
    TestServer srv(scripted_executor(control), {}, 1, 8, [&](triax::service::ServiceConfig& c) { c.token = token; });
    CHECK(srv.get("/health").status == 200);
    check_problem(srv.get("/runs"), 401);
    check_problem(srv.post("/schemes", json::object()), 401);
    check_problem(request(srv, "GET", "/runs", {{"Authorization", "Bearer wrong-token-0123456789"}}), 401);
    CHECK(request(srv, "GET", "/runs", {{"Authorization", "Bearer " + token}}).status == 200);
    const auto page = request(srv, "GET", "/?token=" + token, {});
    CHECK(page.status == 200);
    CHECK(page.text.find("triax_token=" + token + "; Path=/; HttpOnly; SameSite=Strict") != std::string::npos);
    CHECK(request(srv, "GET", "/runs", {{"Cookie", "a=b; triax_token=" + token}}).status == 200);
    check_problem(request(srv, "GET", "/runs?token=" + token.substr(1), {}), 401);
}

TEST_CASE("PUT and PATCH are 405 with Allow, a NUL in a static path is 404", "[server][guard]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    for (const char* m : {"PUT", "PATCH"}) {
        INFO(m);
        const auto r = request(srv, m, "/schemes", {}, "{}");
        INFO(r.text);
        check_problem(r, 405);
        CHECK(r.text.find("Allow: GET, HEAD, POST") != std::string::npos);
    }
    const auto d = request(srv, "DELETE", "/health", {});
    check_problem(d, 405);
    check_problem(request(srv, "PUT", "/nothing/here", {}, "{}"), 404);
    const auto nul = srv.get("/static/index.html%00.png");
    CHECK(nul.status == 404);
    CHECK(nul.content_type != "image/png");
    CHECK(srv.get("/index.html").status == 200);
}

TEST_CASE("GET /datasets lists from the stored header without parsing the datasets", "[server][guard]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const auto up = srv.post("/datasets?format=csv", std::string("confining_kPa,axial_strain_pct,q_kPa\n100,0.5,80\n"),
                             "text/csv");
    REQUIRE(up.status == 201);
    // A listing must not depend on parsing the (large) dataset text.
    srv.service().db.with([](triax::service::Database& db) { db.exec("UPDATE datasets SET dataset_json = 'not parsed'"); });
    const auto list = srv.get("/datasets");
    REQUIRE(list.status == 200);
    REQUIRE(list.body["datasets"].size() == 1);
    CHECK(list.body["datasets"][0]["curves"][0]["points"] == 1);
}

TEST_CASE("datasets stored before the header column get it at start-up", "[server][guard]") {
    ScriptControl control;
    const auto dir = make_temp_dir("backfill");
    {
        TestServer srv(scripted_executor(control), dir);
        REQUIRE(srv.post("/datasets?format=csv", std::string("confining_kPa,axial_strain_pct,q_kPa\n100,0.5,80\n100,1,90\n"),
                         "text/csv")
                    .status == 201);
        srv.service().db.with([](triax::service::Database& db) { db.exec("UPDATE datasets SET header_json = NULL"); });
    }
    TestServer again(scripted_executor(control), dir);
    const auto list = again.get("/datasets");
    REQUIRE(list.body["datasets"].size() == 1);
    CHECK(list.body["datasets"][0]["curves"][0]["points"] == 2);
    again.stop();
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
}
