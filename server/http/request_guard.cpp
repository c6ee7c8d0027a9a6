#include "server/http/request_guard.hpp"

#include "server/http/host_header.hpp"

#include <algorithm>
#include <cctype>

namespace triax::service {

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

bool is_wildcard(const std::string& host) { return host == "0.0.0.0" || host == "::" || host.empty(); }

// The one page load that may carry the token in its URL: the entry link "/?token=T".
bool is_page_entry(const httplib::Request& req) {
    return req.method == "GET" && (req.path == "/" || req.path == "/index.html") && req.has_param("token");
}

std::string cookie_value(const httplib::Request& req, const std::string& name) {
    const std::string cookies = req.get_header_value("Cookie");
    std::size_t pos = 0;
    while (pos < cookies.size()) {
        auto end = cookies.find(';', pos);
        if (end == std::string::npos) end = cookies.size();
        std::string part = cookies.substr(pos, end - pos);
        const auto first = part.find_first_not_of(' ');
        part = first == std::string::npos ? "" : part.substr(first);
        if (part.rfind(name + "=", 0) == 0) return part.substr(name.size() + 1);
        pos = end + 1;
    }
    return "";
}

}  // namespace

bool same_secret(const std::string& a, const std::string& b) {
    if (a.size() != b.size()) return false;
    unsigned char diff = 0;
    for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
    return diff == 0;
}

bool RequestGuard::host_allowed(const std::string& host_header) const {
    const auto host = parse_host_header(host_header);
    if (!host) return false;
    if (host->port != -1 && host->port != config_.port) return false;
    const std::string& name = host->name;
    for (const auto& h : config_.allowed_hosts)
        if (lower(h) == name) return true;
    const std::string bound = lower(config_.host);
    if (name == bound) return true;
    // The loopback names are the same machine whichever of them the user typed; a DNS name
    // is never one of them ("127.0.0.1.evil.example" is a rebinding page's own name).
    if (is_loopback_name(bound) && is_loopback_name(name)) return true;
    // Bound to every interface: any address of the machine may be typed, but never a DNS
    // name other than localhost (a rebinding page brings its own name).
    if (is_wildcard(bound)) return is_ip_literal(*host) || name == "localhost";
    return false;
}

bool RequestGuard::token_presented(const httplib::Request& req) const {
    const std::string auth = req.get_header_value("Authorization");
    if (auth.size() > 7 && lower(auth.substr(0, 7)) == "bearer " && same_secret(auth.substr(7), config_.token)) return true;
    const std::string c = cookie_value(req, "triax_token");
    if (!c.empty() && same_secret(c, config_.token)) return true;
    // In the URL only on the page's entry link, which turns it into the cookie: a URL is
    // logged and kept in the history, so other GETs must not take it there.
    return is_page_entry(req) && same_secret(req.get_param_value("token"), config_.token);
}

std::optional<GuardRefusal> RequestGuard::check(const httplib::Request& req) const {
    // Two Host headers: which one a proxy or cache keys on is anyone's guess (RFC 9112 3.2
    // says answer 400).
    if (req.get_header_value_count("Host") > 1)
        return GuardRefusal{400, "Bad Request", "the request carries more than one Host header"};
    if (!req.has_header("Host") || !host_allowed(req.get_header_value("Host")))
        return GuardRefusal{403, "Forbidden",
                            "Host '" + req.get_header_value("Host") +
                                "' is not this service's address (DNS rebinding guard; add it with --allow-host)"};
    if (req.has_header("Origin")) {
        const std::string origin = req.get_header_value("Origin");
        const std::string prefix = "http://";
        if (lower(origin).rfind(prefix, 0) != 0 || !host_allowed(origin.substr(prefix.size())))
            return GuardRefusal{403, "Forbidden", "requests from origin '" + origin + "' are not accepted"};
    }
    if (!config_.token.empty() && req.path != "/health" && !token_presented(req))
        return GuardRefusal{401, "Unauthorized",
                            "this service requires a token: send 'Authorization: Bearer <token>' or open /?token=<token>"};
    return std::nullopt;
}

std::string RequestGuard::token_cookie(const httplib::Request& req) const {
    if (config_.token.empty() || !is_page_entry(req) || !same_secret(req.get_param_value("token"), config_.token))
        return "";
    return "triax_token=" + config_.token + "; Path=/; HttpOnly; SameSite=Strict";
}

}  // namespace triax::service
