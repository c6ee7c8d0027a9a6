#include "server/store/comparison_store.hpp"

namespace triax::service {

using nlohmann::json;

namespace {

const char* kSelectComparisons = "SELECT id, run_id, dataset_id, result_json, created_at FROM comparisons";

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
    return db_.insert("INSERT INTO comparisons(run_id, dataset_id, result_json, created_at) VALUES (?, ?, ?, ?)",
                      run_id, dataset_id, result.dump(), created_at);
}

json ComparisonStore::get(std::int64_t id) {
    return db_.row(std::string(kSelectComparisons) + " WHERE id = ?", id, NotFound::row("comparison", id), comparison_row);
}

json ComparisonStore::page(const PageRequest& page) {
    return db_.with([&](Database& db) {
        return read_page(db, page, "comparisons", kSelectComparisons, "id", [](Statement& st) {
            auto c = comparison_row(st);
            for (auto& curve : c["curves"]) curve.erase("residual");
            return c;
        });
    });
}

}  // namespace triax::service
