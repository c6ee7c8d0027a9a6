#include "server/store/packing_store.hpp"

namespace triax::service {

using nlohmann::json;

std::int64_t PackingStore::insert(const std::string& name, const std::string& format, std::int64_t grains,
                                  const json& packing, const std::string& created_at) {
    const auto text = packing.dump();
    return db_.transaction([&](Database& db) {
        auto ins = db.prepare("INSERT INTO packings(name, format, grains, packing_json, created_at) VALUES (?, ?, ?, ?, ?)");
        ins.bind_all(name, format, grains, text, created_at);
        ins.run();
        return db.last_insert_id();
    });
}

json PackingStore::get(std::int64_t id) {
    return db_.with([&](Database& db) {
        auto st = db.prepare("SELECT id, name, format, grains, packing_json, created_at FROM packings WHERE id = ?");
        st.bind_all(id);
        if (!st.step()) throw NotFound("packing " + std::to_string(id) + " does not exist");
        return json{{"id", st.int64(0)},     {"name", st.text(1)},        {"format", st.text(2)},
                    {"grains", st.int64(3)}, {"created_at", st.text(5)}, {"packing", json::parse(st.text(4))}};
    });
}

json PackingStore::packing(std::int64_t id, const std::string& field) {
    const auto text = db_.with([&](Database& db) {
        auto st = db.prepare("SELECT packing_json FROM packings WHERE id = ?");
        st.bind_all(id);
        if (!st.step()) throw NotFound("packing " + std::to_string(id) + " does not exist", field);
        return st.text(0);
    });
    return json::parse(text);
}

}  // namespace triax::service
