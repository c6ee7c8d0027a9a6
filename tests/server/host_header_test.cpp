// DNS rebinding past the Host check: a page on "127.0.0.1.evil.example" reaches a loopback
// service under its own name; the Host header must be read whole, not by its prefix, and a
// request with two Host headers is refused. Also: the token in a URL only on the page's
// entry link.
#include "server/http/host_header.hpp"
#include "service_fixture.hpp"

using namespace triax::test;
using triax::service::is_loopback_name;
using triax::service::parse_host_header;

namespace {
int raw_status(const TestServer& srv, const std::string& method, const std::string& path,
               const std::vector<std::string>& lines, const std::string& body = "") {
    return srv.raw(method, path, lines, body).first;
}
}  // namespace

TEST_CASE("parse_host_header reads name and port strictly", "[server][guard][host]") {
    auto h = parse_host_header("127.0.0.1:8080");
    REQUIRE(h);
    CHECK(h->name == "127.0.0.1");
    CHECK(h->port == 8080);
    h = parse_host_header("[::1]:9");
    REQUIRE(h);
    CHECK(h->name == "::1");
    CHECK(h->ipv6);
    CHECK(h->port == 9);
    h = parse_host_header("LocalHost");
    REQUIRE(h);
    CHECK(h->name == "localhost");
    CHECK(h->port == -1);
    for (const char* bad : {"", ":80", "a:b:c", "::1", "[::1", "[evil]:80", "[::1]x", "host:", "host:123456",
                            "host:-1", "user@host", "host/path", "a..b", ".a", "a."}) {
        INFO(bad);
        CHECK_FALSE(parse_host_header(bad));
    }
}

TEST_CASE("only exact loopback literals are loopback names", "[server][guard][host]") {
    for (const char* yes : {"localhost", "127.0.0.1", "127.1.2.3", "127.255.255.255", "::1"}) {
        INFO(yes);
        CHECK(is_loopback_name(yes));
    }
    for (const char* no : {"127.0.0.1.evil.example", "127.evil.example", "127.1", "127.0.0.01", "0177.0.0.1",
                           "128.0.0.1", "localhost.evil.example", "::2", "127.0.0.256"}) {
        INFO(no);
        CHECK_FALSE(is_loopback_name(no));
    }
}

TEST_CASE("Host 127.0.0.1.evil.example is 403 on GET and POST /runs, two Host headers are 400",
          "[server][guard][host]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const std::string port = std::to_string(srv.port());
    const std::string evil = "127.0.0.1.evil.example:" + port;
    CHECK(raw_status(srv, "GET", "/runs", {"Host: " + evil}) == 403);
    CHECK(raw_status(srv, "POST", "/runs",
                     {"Host: " + evil, "Origin: http://" + evil, "Content-Type: application/json"},
                     R"({"scheme": {}})") == 403);
    CHECK(raw_status(srv, "GET", "/runs", {"Host: 127.evil.example:" + port}) == 403);
    // Two Host headers, the good one first: which one counts is ambiguous.
    CHECK(raw_status(srv, "GET", "/runs", {"Host: 127.0.0.1:" + port, "Host: evil.example:" + port}) == 400);
    CHECK(raw_status(srv, "GET", "/runs", {"Host: 127.0.0.1:" + port, "Host: 127.0.0.1:" + port}) == 400);
    // The loopback literals are still this machine.
    for (const std::string& good : {"127.0.0.1:" + port, "127.0.0.2:" + port, "localhost:" + port, "[::1]:" + port}) {
        INFO(good);
        CHECK(raw_status(srv, "GET", "/runs", {"Host: " + good}) == 200);
    }
    CHECK(control.started == 0);
    CHECK(srv.get("/runs").body["total"] == 0);
}

TEST_CASE("the token is taken from the URL only on the page's entry link", "[server][guard][host]") {
    ScriptControl control;
    const std::string token = "s3cret-token-0123456789";
    TestServer srv(scripted_executor(control), {}, 1, 8, [&](triax::service::ServiceConfig& c) { c.token = token; });
    const std::string host = "Host: 127.0.0.1:" + std::to_string(srv.port());
    CHECK(raw_status(srv, "GET", "/?token=" + token, {host}) == 200);
    CHECK(raw_status(srv, "GET", "/runs?token=" + token, {host}) == 401);
    CHECK(raw_status(srv, "GET", "/datasets?token=" + token, {host}) == 401);
    CHECK(raw_status(srv, "GET", "/runs", {host, "Authorization: Bearer " + token}) == 200);
}
