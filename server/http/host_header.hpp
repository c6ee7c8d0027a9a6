#pragma once
// The Host header (RFC 9110 7.2, RFC 3986 3.2.2) read strictly, for the DNS-rebinding guard:
// "name[:port]" with a registered name of letters, digits, '.' and '-', or a bracketed IPv6
// literal "[v6][:port]". Anything else (two colons without brackets, a port that is not
// 1-5 digits, userinfo, a trailing dot) is not a Host this service answers to.
#include <optional>
#include <string>
#include <string_view>

namespace triax::service {

struct HostHeader {
    std::string name;   // lower case, IPv6 without the brackets
    int port = -1;      // -1 when the header names no port
    bool ipv6 = false;  // the name was a bracketed IPv6 literal
};

// nullopt when `text` is not a well-formed Host value.
std::optional<HostHeader> parse_host_header(std::string_view text);

// A dotted-quad IPv4 literal: exactly four decimal octets in 0..255, no leading zeros
// ("127.1" and "0177.0.0.1" are read differently by different resolvers, so refused).
bool is_ipv4_literal(const std::string& name);
// An IP literal: a dotted quad, or an IPv6 address (the name of a bracketed Host).
bool is_ip_literal(const HostHeader& h);
// The loopback names whichever way the user typed them: "localhost", 127.0.0.0/8 as a
// dotted quad, "::1". A DNS name that merely starts with "127." is not one of them.
bool is_loopback_name(const std::string& name);

}  // namespace triax::service
