#pragma once
// The domain error of a store: the row asked for does not exist. The service's one
// exception handler answers it 404 (with `field`, the JSON pointer of the request member
// that named the id, when the caller gave one).
#include <cstdint>
#include <stdexcept>
#include <string>

namespace triax::service {

struct NotFound : std::runtime_error {
    std::string field;
    explicit NotFound(const std::string& what, std::string field = "")
        : std::runtime_error(what), field(std::move(field)) {}
    // "<noun> <id> does not exist".
    static NotFound row(const std::string& noun, std::int64_t id, std::string field = "") {
        return NotFound(noun + " " + std::to_string(id) + " does not exist", std::move(field));
    }
};

}  // namespace triax::service
