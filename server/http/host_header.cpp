#include "server/http/host_header.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <cctype>

namespace triax::service {

namespace {

bool all_digits(std::string_view s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); });
}

// A port of 1-5 digits in 0..65535, or -1.
int parse_port(std::string_view s) {
    if (!all_digits(s) || s.size() > 5) return -1;
    const int p = std::stoi(std::string(s));
    return p <= 65535 ? p : -1;
}

// RFC 3986 reg-name restricted to what DNS names use: letters, digits, '-' and '.', with no
// empty label (no leading, trailing or doubled dot).
bool is_dns_name(std::string_view s) {
    if (s.empty() || s.size() > 253 || s.front() == '.' || s.back() == '.' || s.find("..") != std::string_view::npos)
        return false;
    return std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isalnum(c) || c == '-' || c == '.'; });
}

bool is_ipv6_text(const std::string& s) {
    in6_addr a{};
    return inet_pton(AF_INET6, s.c_str(), &a) == 1;
}

std::string lower(std::string_view s) {
    std::string out(s);
    std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return out;
}

}  // namespace

std::optional<HostHeader> parse_host_header(std::string_view text) {
    HostHeader h;
    std::string_view rest;
    if (!text.empty() && text.front() == '[') {
        const auto close = text.find(']');
        if (close == std::string_view::npos) return std::nullopt;
        h.name = lower(text.substr(1, close - 1));
        h.ipv6 = true;
        if (!is_ipv6_text(h.name)) return std::nullopt;
        rest = text.substr(close + 1);
        if (!rest.empty() && rest.front() != ':') return std::nullopt;
    } else {
        const auto colon = text.find(':');
        if (colon != std::string_view::npos && text.find(':', colon + 1) != std::string_view::npos) return std::nullopt;
        h.name = lower(text.substr(0, colon));
        if (!is_dns_name(h.name)) return std::nullopt;
        rest = colon == std::string_view::npos ? std::string_view() : text.substr(colon);
    }
    if (!rest.empty()) {
        h.port = parse_port(rest.substr(1));
        if (h.port < 0) return std::nullopt;
    }
    return h;
}

bool is_ipv4_literal(const std::string& name) {
    in_addr a{};
    // glibc's inet_pton takes exactly four decimal parts and refuses leading zeros.
    return inet_pton(AF_INET, name.c_str(), &a) == 1;
}

bool is_ip_literal(const HostHeader& h) { return h.ipv6 ? is_ipv6_text(h.name) : is_ipv4_literal(h.name); }

bool is_loopback_name(const std::string& name) {
    if (name == "localhost") return true;
    if (is_ipv4_literal(name)) return name.rfind("127.", 0) == 0;
    in6_addr a{};
    return inet_pton(AF_INET6, name.c_str(), &a) == 1 && IN6_IS_ADDR_LOOPBACK(&a);
}

}  // namespace triax::service
