#pragma once
// Who may talk to triaxd. The service listens on loopback next to a browser, so a web page
// from another site must not be able to drive it:
//  - Host must name the bound address (or localhost / an IP literal when bound to a
//    wildcard address): a DNS-rebinding page reaches us under its own name and is refused.
//    The header is parsed strictly (host_header.hpp); two Host headers are 400.
//  - Origin, when a browser sends one, must be this service's own origin.
//  - With a token (--token / TRIAX_TOKEN) every route but /health needs
//    "Authorization: Bearer <token>" or the cookie the page gets from "/?token=<token>"
//    (HttpOnly, SameSite=Strict: another site's requests never carry it). Only that entry
//    link ("/" or "/index.html") takes the token as a query parameter.
// JSON endpoints additionally require Content-Type application/json (parse_body, 415): a
// cross-site form or fetch without preflight can only send text/plain, urlencoded or
// multipart bodies.
#include <httplib.h>

#include <optional>
#include <string>
#include <vector>

namespace triax::service {

struct GuardConfig {
    std::string host;                        // the bound host, e.g. "127.0.0.1" or "0.0.0.0"
    int port = 0;                            // the bound port
    std::vector<std::string> allowed_hosts;  // extra Host names (--allow-host), without port
    std::string token;                       // empty = no token required
};

// What the guard refuses: status 400/401/403 and why.
struct GuardRefusal {
    int status;
    std::string title, detail;
};

class RequestGuard {
public:
    explicit RequestGuard(GuardConfig c) : config_(std::move(c)) {}
    void set_port(int port) { config_.port = port; }
    const GuardConfig& config() const { return config_; }

    // nullopt when the request may proceed.
    std::optional<GuardRefusal> check(const httplib::Request& req) const;
    // The Set-Cookie value that carries the token for the page, when `req` presents the
    // token as ?token= (the page's entry link); empty otherwise.
    std::string token_cookie(const httplib::Request& req) const;

private:
    bool host_allowed(const std::string& host_header) const;
    bool token_presented(const httplib::Request& req) const;
    GuardConfig config_;
};

// Constant-time comparison of two secrets.
bool same_secret(const std::string& a, const std::string& b);

}  // namespace triax::service
