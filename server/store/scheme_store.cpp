#include "server/store/scheme_store.hpp"

namespace triax::service {

using nlohmann::json;

std::int64_t SchemeStore::insert(const std::string& name, const json& scheme) {
    return db_.insert("INSERT INTO schemes(name, scheme_json, created_at) VALUES (?, ?, ?)", name, scheme.dump(),
                      utc_now());
}

json SchemeStore::get(std::int64_t id) {
    return db_.row("SELECT id, name, scheme_json, created_at FROM schemes WHERE id = ?", id,
                   NotFound::row("scheme", id), [](Statement& st) {
                       return json{{"id", st.int64(0)},
                                   {"name", st.text(1)},
                                   {"scheme", json::parse(st.text(2))},
                                   {"created_at", st.text(3)}};
                   });
}

json SchemeStore::scheme(std::int64_t id, const std::string& field) {
    // The text is read under the database lock, parsed outside it.
    const auto text = db_.row("SELECT scheme_json FROM schemes WHERE id = ?", id, NotFound::row("scheme", id, field),
                              [](Statement& st) { return st.text(0); });
    return json::parse(text);
}

std::string SchemeStore::name_in(Database& tx, std::int64_t id, const std::string& field) {
    auto st = tx.prepare("SELECT name FROM schemes WHERE id = ?");
    st.bind_all(id);
    if (!st.step()) throw NotFound::row("scheme", id, field);
    return st.text(0);
}

json SchemeStore::page(const PageRequest& page) {
    return db_.with([&](Database& db) {
        return read_page(db, page, "schemes", "SELECT id, name, created_at FROM schemes", "id", [](Statement& st) {
            return json{{"id", st.int64(0)}, {"name", st.text(1)}, {"created_at", st.text(2)}};
        });
    });
}

}  // namespace triax::service
