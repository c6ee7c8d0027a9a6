#include "server/http/stored_document.hpp"

#include "server/http/problem.hpp"

#include <memory>

namespace triax::service {

void send_stored_member(Database& db, httplib::Response& res, nlohmann::json head, const std::string& key,
                        const StoredValue& value) {
    head.erase(key);
    const auto size = db.with([&](Database& d) { return d.read_range(value.table, value.column, value.rowid, 0, 0); });
    if (!size) throw not_found(std::string("the stored ") + value.column + " of " + value.table + " " +
                               std::to_string(value.rowid) + " is gone");
    // {"a":1,...} -> {"a":1,...,"key":<stored>}  (an empty head gives {"key":<stored>})
    auto prefix = std::make_shared<std::string>(head.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
    prefix->pop_back();
    *prefix += (head.empty() ? "" : ",") + nlohmann::json(key).dump() + ":";
    const std::size_t stored = size->total;
    const std::size_t total = prefix->size() + stored + 1;
    res.status = 200;
    res.set_content_provider(
        total, "application/json",
        [&db, value, prefix, stored](std::size_t offset, std::size_t, httplib::DataSink& sink) {
            if (offset < prefix->size()) return sink.write(prefix->data() + offset, prefix->size() - offset);
            const std::size_t at = offset - prefix->size();
            if (at >= stored) return sink.write("}", 1);
            // One slice under the connection, written outside it.
            const auto slice = db.with([&](Database& d) {
                return d.read_range(value.table, value.column, value.rowid, at, kStoredSliceBytes);
            });
            if (!slice || slice->total != stored || slice->bytes.empty()) return false;  // deleted meanwhile
            return sink.write(slice->bytes.data(), slice->bytes.size());
        });
}

}  // namespace triax::service
