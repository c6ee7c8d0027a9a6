#pragma once
// A JSON answer one of whose members is a large JSON text kept in the store (a dataset's
// readings: megabytes): the small part is built as usual, the stored text is copied to the
// socket in slices read in place from SQLite (Database::read_range) as the client takes
// them. The answer has a Content-Length; the server holds one slice per answer, never the
// value whole nor its parsed form (a parsed 11 MB document is ten times that in memory).
#include "server/store/database.hpp"

#include <httplib.h>
#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <string>

namespace triax::service {

// Where the stored JSON text is: a TEXT column of one row.
struct StoredValue {
    const char* table;
    const char* column;
    std::int64_t rowid;
};

// Bytes read from the store per slice (and per hold of the connection).
constexpr std::size_t kStoredSliceBytes = 256 * 1024;

// Answers 200 with `head` (an object) plus the member `key` whose value is the stored text.
// The text must be JSON as stored by the service. If the row is deleted while the answer
// is being sent, the connection is closed short of the Content-Length (the client sees a
// truncated answer, not a wrong one); if it is gone before, 404.
void send_stored_member(Database& db, httplib::Response& res, nlohmann::json head, const std::string& key,
                        const StoredValue& value);

}  // namespace triax::service
