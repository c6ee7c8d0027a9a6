// Clients that open connections and send their request heads slowly, or never finish them,
// must not take the HTTP threads from everyone else (cpp-httplib gives each connection a
// thread from accept on: 330 such connections once made /health time out). The gate holds
// them without a thread, ends them after the head timeout, and keeps only the newest ones
// past its cap; a body that trickles in ends at the body timeout.
#include "service_fixture.hpp"

#include <poll.h>

using namespace triax::test;

namespace {

int open_connection(int port) { return connect_loopback(port, 0); }  // no timeouts: the server decides

// A connection that has sent part of a head and stops there.
int unfinished_head(int port) {
    const int fd = open_connection(port);
    const std::string part = "GET /health HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\nX-Slow: ";
    send(fd, part.data(), part.size(), MSG_NOSIGNAL);
    return fd;
}

// What the server sends before it closes `fd` ("closed" if nothing), waiting at most `ms`;
// "open" appended if it is still open then.
std::string until_closed(int fd, int ms) {
    std::string got;
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
    while (std::chrono::steady_clock::now() < end) {
        pollfd p{fd, POLLIN, 0};
        if (poll(&p, 1, 50) <= 0) continue;
        char buf[1024];
        const ssize_t n = recv(fd, buf, sizeof buf, 0);
        if (n <= 0) return got.empty() ? "closed" : got;
        got.append(buf, static_cast<std::size_t>(n));
    }
    return got + "open";
}

}  // namespace

TEST_CASE("100 connections holding unfinished heads do not starve /health (24 HTTP threads)", "[server][guard][slow-client]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));  // 24 HTTP threads
    std::vector<int> slow;
    for (int i = 0; i < 100; ++i) slow.push_back(unfinished_head(srv.port()));
    for (int i = 0; i < 200 && srv.service().http.connections_waiting() < 100; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    CHECK(srv.service().http.connections_waiting() >= 100);
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < 20; ++i) CHECK(srv.get("/health").status == 200);
    CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::seconds(2));
    // A kept-alive client is served request after request over one connection.
    auto c = srv.client();
    c.set_keep_alive(true);
    for (int i = 0; i < 5; ++i) {
        auto r = c.Get("/health");
        REQUIRE(r);
        CHECK(r->status == 200);
    }
    for (int fd : slow) close(fd);
}

TEST_CASE("an unfinished head is answered 408 and closed after the head timeout", "[server][guard][slow-client]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control), {}, 1, 8,
                   [](triax::service::ServiceConfig& c) { c.head_timeout = std::chrono::milliseconds(500); });
    const int fd = unfinished_head(srv.port());
    const auto t0 = std::chrono::steady_clock::now();
    const std::string got = until_closed(fd, 5000);
    const auto waited = std::chrono::steady_clock::now() - t0;
    close(fd);
    CHECK(got.rfind("HTTP/1.1 408", 0) == 0);
    CHECK(waited >= std::chrono::milliseconds(400));
    CHECK(waited < std::chrono::seconds(2));
    // A silent connection (no byte at all) is closed as well.
    const int silent = open_connection(srv.port());
    CHECK(until_closed(silent, 5000) == "closed");
    close(silent);
}

TEST_CASE("past the cap of waiting connections the longest-waiting ones are closed", "[server][guard][slow-client]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control), {}, 1, 8,
                   [](triax::service::ServiceConfig& c) { c.max_waiting_connections = 32; });
    std::vector<int> slow;
    for (int i = 0; i < 48; ++i) {
        slow.push_back(unfinished_head(srv.port()));
        std::this_thread::sleep_for(std::chrono::milliseconds(2));  // a definite order
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    CHECK(srv.service().http.connections_waiting() <= 32);
    int closed_first = 0, open_last = 0;
    for (int i = 0; i < 16; ++i) closed_first += until_closed(slow[static_cast<std::size_t>(i)], 100) == "closed";
    for (int i = 40; i < 48; ++i) open_last += until_closed(slow[static_cast<std::size_t>(i)], 50) == "open";
    CHECK(closed_first == 16);
    CHECK(open_last == 8);
    CHECK(srv.get("/health").status == 200);
    for (int fd : slow) close(fd);
}

TEST_CASE("a request body that trickles in ends at the body timeout", "[server][guard][slow-client]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control), {}, 1, 8,
                   [](triax::service::ServiceConfig& c) { c.body_timeout = std::chrono::milliseconds(500); });
    const int fd = open_connection(srv.port());
    const std::string head = "POST /schemes HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(srv.port()) +
                             "\r\nContent-Type: application/json\r\nContent-Length: 100\r\n\r\n{";
    send(fd, head.data(), head.size(), MSG_NOSIGNAL);
    const auto t0 = std::chrono::steady_clock::now();
    std::string got = "open";
    // One byte every 200 ms: each read is well within the 10 s read timeout.
    for (int i = 0; i < 30 && got == "open"; ++i) {
        send(fd, " ", 1, MSG_NOSIGNAL);
        got = until_closed(fd, 200);
    }
    const auto waited = std::chrono::steady_clock::now() - t0;
    close(fd);
    INFO(got);
    CHECK(got.rfind("HTTP/1.1 400", 0) == 0);  // the body could not be read completely
    CHECK(got.find("open") == std::string::npos);  // and the connection is closed
    CHECK(waited < std::chrono::seconds(3));
    CHECK(srv.get("/schemes").body["total"] == 0);
}
