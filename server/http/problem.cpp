#include "server/http/problem.hpp"

#include "server/io/bounded_json.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>

namespace triax::service {

nlohmann::json problem_json(const ApiError& e, const std::string& instance) {
    nlohmann::json p{{"type", "about:blank"}, {"title", e.title}, {"status", e.status}, {"detail", e.what()},
                     {"instance", instance}};
    if (e.field) p["field"] = *e.field;
    if (e.line) p["line"] = *e.line;
    if (e.column) p["column"] = *e.column;
    if (e.limit) p["limit"] = *e.limit;
    if (e.request_id) p["request_id"] = *e.request_id;
    return p;
}

void send_problem(httplib::Response& res, const ApiError& e, const std::string& instance) {
    res.status = e.status;
    if (e.request_id) res.set_header("X-Request-Id", *e.request_id);
    // `replace`: a detail quoting bad bytes of an upload must still be sent; a throwing
    // dump here would escape the exception handler and end the process.
    res.set_content(problem_json(e, instance).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                    "application/problem+json");
}

void send_json(httplib::Response& res, const nlohmann::json& body, int status) {
    res.status = status;
    res.set_content(body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), "application/json");
}

std::size_t invalid_utf8_at(std::string_view s) {
    std::size_t i = 0;
    while (i < s.size()) {
        const auto c = static_cast<unsigned char>(s[i]);
        // Lead byte: payload length and the smallest code point it may encode (no overlongs).
        std::size_t n = 0;
        std::uint32_t cp = 0, min = 0;
        if (c < 0x80) { ++i; continue; }
        if ((c & 0xE0) == 0xC0) { n = 1; cp = c & 0x1F; min = 0x80; }
        else if ((c & 0xF0) == 0xE0) { n = 2; cp = c & 0x0F; min = 0x800; }
        else if ((c & 0xF8) == 0xF0) { n = 3; cp = c & 0x07; min = 0x10000; }
        else return i;
        for (std::size_t k = 1; k <= n; ++k) {
            if (i + k >= s.size()) return i;
            const auto b = static_cast<unsigned char>(s[i + k]);
            if ((b & 0xC0) != 0x80) return i;
            cp = (cp << 6) | (b & 0x3F);
        }
        if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return i;
        i += n + 1;
    }
    return std::string_view::npos;
}

void check_resource_name(std::string_view name, const std::string& what) {
    if (invalid_utf8_at(name) != std::string_view::npos) throw bad_request(what + " is not UTF-8 text");
    // Characters, not bytes: continuation bytes (10xxxxxx) do not start one.
    const auto chars = static_cast<std::size_t>(
        std::count_if(name.begin(), name.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
    if (chars > kMaxNameChars)
        throw unprocessable(what + " is longer than " + std::to_string(kMaxNameChars) + " characters")
            .with_limit("name length <= " + std::to_string(kMaxNameChars));
    if (std::any_of(name.begin(), name.end(), [](unsigned char c) { return c < 0x20 || c == 0x7f; }))
        throw unprocessable(what + " holds a control character (tab, newline, ...)");
}

nlohmann::json parse_body(const httplib::Request& req) {
    if (req.body.empty()) throw bad_request("request body is empty; a JSON document is expected");
    // application/json only (parameters such as charset allowed): a cross-site form or a
    // fetch without preflight can send text/plain, never application/json.
    const std::string type = req.get_header_value("Content-Type");
    const std::string media = type.substr(0, type.find(';'));
    std::string trimmed;
    for (char c : media)
        if (c != ' ' && c != '\t') trimmed += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (trimmed != "application/json")
        throw ApiError(415, "Unsupported Media Type",
                       "this endpoint takes a JSON body with Content-Type: application/json" +
                           (type.empty() ? std::string() : ", got '" + type + "'"));

    try {
        return io::parse_bounded_json(req.body);
    } catch (const io::JsonLimitError& e) {
        if (e.syntax) throw bad_request(std::string("request body is ") + e.what());
        throw unprocessable(std::string("request body refused: ") + e.what()).at_field(e.pointer);
    }
}

std::int64_t body_integer(const nlohmann::json& v, const std::string& pointer, std::int64_t lo, std::int64_t hi) {
    const std::string name = pointer.empty() ? std::string("the body") : pointer.substr(pointer.rfind('/') + 1);
    const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    if (!v.is_number_integer()) throw unprocessable(name + " must be an integer in " + range).at_field(pointer);
    const bool beyond = v.is_number_unsigned() && v.get<std::uint64_t>() > static_cast<std::uint64_t>(hi);
    const std::int64_t n = beyond ? hi : v.get<std::int64_t>();
    if (beyond || n < lo || n > hi)
        throw unprocessable(name + " = " + v.dump() + " is outside " + range)
            .at_field(pointer)
            .with_limit(std::to_string(lo) + " <= " + name + " <= " + std::to_string(hi));
    return n;
}

std::int64_t path_id(const httplib::Request& req, std::size_t index) {
    const std::string s = req.matches.size() > index ? std::string(req.matches[index]) : std::string();
    std::int64_t v = 0;
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || p != s.data() + s.size() || v <= 0) throw not_found("no resource with id '" + s + "'");
    return v;
}

std::optional<double> query_number(const httplib::Request& req, const std::string& name) {
    if (!req.has_param(name.c_str())) return std::nullopt;
    const auto s = req.get_param_value(name.c_str());
    try {
        std::size_t used = 0;
        double v = std::stod(s, &used);
        if (used != s.size() || !std::isfinite(v)) throw std::invalid_argument(s);
        return v;
    } catch (const std::exception&) {
        throw bad_request("query parameter '" + name + "' must be a finite number, got '" + s + "'");
    }
}

std::optional<std::int64_t> query_int(const httplib::Request& req, const std::string& name, std::int64_t lo,
                                      std::int64_t hi) {
    if (!req.has_param(name.c_str())) return std::nullopt;
    const auto s = req.get_param_value(name.c_str());
    std::int64_t v = 0;
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || p != s.data() + s.size())
        throw bad_request("query parameter '" + name + "' must be an integer, got '" + s + "'");
    if (v < lo || v > hi)
        throw unprocessable("query parameter '" + name + "' = " + s + " is outside [" + std::to_string(lo) + ", " +
                            std::to_string(hi) + "]")
            .with_limit(std::to_string(lo) + " <= " + name + " <= " + std::to_string(hi));
    return v;
}

}  // namespace triax::service
