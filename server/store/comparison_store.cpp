#include "server/store/comparison_store.hpp"

namespace triax::service {

using nlohmann::json;

namespace {

const char* kSelect = "SELECT id, run_id, dataset_id, result_json, created_at FROM comparisons";

json comparison_row(Statement& st) {
    json out = json::parse(st.text(3));
    out["id"] = st.int64(0);
    out["run_id"] = st.int64(1);
    out["dataset_id"] = st.int64(2);
    out["created_at"] = st.text(4);
    return out;
}

}  // namespace

std::int64_t ComparisonStore::insert(std::int64_t run_id, std::int64_t dataset_id, const json& result,
                                     const std::string& created_at) {
    const auto text = result.dump();
    return db_.transaction([&](Database& db) {
        auto ins = db.prepare("INSERT INTO comparisons(run_id, dataset_id, result_json, created_at) VALUES (?, ?, ?, ?)");
        ins.bind_all(run_id, dataset_id, text, created_at);
        ins.run();
        return db.last_insert_id();
    });
}

json ComparisonStore::get(std::int64_t id) {
    return db_.with([&](Database& db) {
        auto st = db.prepare(std::string(kSelect) + " WHERE id = ?");
        st.bind_all(id);
        if (!st.step()) throw NotFound("comparison " + std::to_string(id) + " does not exist");
        return comparison_row(st);
    });
}

json ComparisonStore::page(const PageRequest& page) {
    return db_.with([&](Database& db) {
        return read_page(db, page, "comparisons", kSelect, "id", [](Statement& st) {
            auto c = comparison_row(st);
            for (auto& curve : c["curves"]) curve.erase("residual");
            return c;
        });
    });
}

}  // namespace triax::service
