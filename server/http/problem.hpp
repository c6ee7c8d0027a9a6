#pragma once
// RFC 7807 problem details. Handlers throw ApiError; the one exception handler of the
// server turns it (or any other exception) into `application/problem+json` with the
// JSON pointer of the faulty field, or the line/column of an uploaded file.
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace triax::service {

struct ApiError : std::runtime_error {
    int status;
    std::string title;
    std::optional<std::string> field;  // JSON pointer into the request body
    std::optional<int> line, column;   // position in an uploaded file (1-based)
    std::optional<std::string> limit;  // the limit that was exceeded, e.g. "particle_count <= 200000"
    std::optional<std::string> request_id;  // a 500: the id under which stderr has the cause
    ApiError(int status, std::string title, const std::string& detail)
        : std::runtime_error(detail), status(status), title(std::move(title)) {}
    ApiError& at_field(std::string pointer) { field = std::move(pointer); return *this; }
    ApiError& at(int l, int c) { line = l; column = c; return *this; }
    ApiError& with_limit(std::string l) { limit = std::move(l); return *this; }
};

inline ApiError not_found(const std::string& what) { return ApiError(404, "Not Found", what); }
inline ApiError bad_request(const std::string& detail) { return ApiError(400, "Bad Request", detail); }
inline ApiError unprocessable(const std::string& detail) { return ApiError(422, "Unprocessable Entity", detail); }
inline ApiError conflict(const std::string& detail) { return ApiError(409, "Conflict", detail); }

nlohmann::json problem_json(const ApiError& e, const std::string& instance);
void send_problem(httplib::Response& res, const ApiError& e, const std::string& instance);
void send_json(httplib::Response& res, const nlohmann::json& body, int status = 200);

// Byte offset of the first byte that is not well-formed UTF-8, or npos. Stored text is
// served as JSON, which must be UTF-8: bad bytes are refused at the door, not at reading.
std::size_t invalid_utf8_at(std::string_view s);
// The name a client gives a stored resource (`what` names it in the refusal, e.g. "query
// parameter 'name'"): UTF-8 text (400), at most kMaxNameChars characters and no control
// characters (422): it is shown in lists and on the page.
constexpr std::size_t kMaxNameChars = 200;
void check_resource_name(std::string_view name, const std::string& what);
// Parses a request body as JSON or throws 400 naming the byte offset.
nlohmann::json parse_body(const httplib::Request& req);
// An integer member of a request body in [lo, hi], or 422 naming `pointer`; an unsigned
// value beyond int64 (2^63) is out of range, not wrapped to a negative number.
std::int64_t body_integer(const nlohmann::json& v, const std::string& pointer, std::int64_t lo, std::int64_t hi);
// Integer path parameter (matches[1] by default) or 404.
std::int64_t path_id(const httplib::Request& req, std::size_t index = 1);
// Optional query parameters with a clear 400 when malformed.
std::optional<double> query_number(const httplib::Request& req, const std::string& name);
std::optional<std::int64_t> query_int(const httplib::Request& req, const std::string& name, std::int64_t lo,
                                      std::int64_t hi);

}  // namespace triax::service
