#pragma once
// Bounded JSON parsing for everything that arrives from outside (request bodies, uploaded
// JSON datasets, the CLI's scheme file). nlohmann's parser is iterative, but building,
// dumping and validating a document recurse over its depth, and a 100 KB body can nest
// 50,000 levels: the limits are checked by the parser callback while the document is
// built, so no bad value is ever held whole or walked recursively. Refused: nesting deeper
// than max_depth, strings and keys longer than max_string_bytes, arrays or objects with
// more than max_elements members, duplicate keys in an object (RFC 8259 leaves them
// undefined; the reader would keep one silently).
#include <nlohmann/json.hpp>

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace triax::io {

struct JsonLimits {
    int max_depth = 32;                       // nesting of arrays and objects (the top level is 1)
    std::size_t max_string_bytes = 64 * 1024; // every string value and key
    std::size_t max_elements = 2'000'000;     // members of one array or object
};

// A limit or a syntax error. `pointer` is the JSON pointer of the offending value (or of
// the container it was in), empty for the top level; `byte` is the offset in the text
// where the parser stood (0 when unknown).
struct JsonLimitError : std::runtime_error {
    std::string pointer;
    std::size_t byte = 0;
    bool syntax = false;  // true: the text is not JSON at all (400), false: a limit (422)
    JsonLimitError(const std::string& msg, std::string ptr, std::size_t at, bool is_syntax)
        : std::runtime_error(msg), pointer(std::move(ptr)), byte(at), syntax(is_syntax) {}
};

// Parses `text` under `limits` or throws JsonLimitError.
nlohmann::json parse_bounded_json(std::string_view text, const JsonLimits& limits = {});

// JSON pointer escaping of one reference token ("~" -> "~0", "/" -> "~1").
std::string json_pointer_token(std::string_view key);

}  // namespace triax::io
