#include "server/store/packing_store.hpp"

namespace triax::service {

using nlohmann::json;

std::int64_t PackingStore::insert(const std::string& name, const std::string& format, std::int64_t grains,
                                  const json& packing, const std::string& created_at) {
    return db_.insert("INSERT INTO packings(name, format, grains, packing_json, created_at) VALUES (?, ?, ?, ?, ?)",
                      name, format, grains, packing.dump(), created_at);
}

json PackingStore::get(std::int64_t id) {
    return db_.row("SELECT id, name, format, grains, packing_json, created_at FROM packings WHERE id = ?", id,
                   NotFound::row("packing", id), [](Statement& st) {
                       return json{{"id", st.int64(0)},        {"name", st.text(1)},
                                   {"format", st.text(2)},     {"grains", st.int64(3)},
                                   {"created_at", st.text(5)}, {"packing", json::parse(st.text(4))}};
                   });
}

json PackingStore::packing(std::int64_t id, const std::string& field) {
    // The text is read under the database lock, parsed outside it.
    const auto text = db_.row("SELECT packing_json FROM packings WHERE id = ?", id, NotFound::row("packing", id, field),
                              [](Statement& st) { return st.text(0); });
    return json::parse(text);
}

}  // namespace triax::service
