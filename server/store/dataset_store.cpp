#include "server/store/dataset_store.hpp"

namespace triax::service {

using nlohmann::json;

namespace {

DatasetRow dataset_row(Statement& st) {
    DatasetRow r;
    r.id = st.int64(0);
    r.name = st.text(1);
    r.format = st.text(2);
    r.created_at = st.text(3);
    if (!st.is_null(4)) r.header = json::parse(st.text(4));
    return r;
}

const char* kSelectDatasets = "SELECT id, name, format, created_at, header_json FROM datasets";

}  // namespace

std::int64_t DatasetStore::insert(const std::string& name, const std::string& format, const std::string& dataset_json,
                                  const json& header, const std::string& created_at) {
    return db_.insert(
        "INSERT INTO datasets(name, format, dataset_json, header_json, created_at) VALUES (?, ?, ?, ?, ?)", name,
        format, dataset_json, header.dump(), created_at);
}

std::string DatasetStore::dataset_text(std::int64_t id, std::string* name) {
    return db_.row("SELECT name, dataset_json FROM datasets WHERE id = ?", id, NotFound::row("dataset", id),
                   [&](Statement& st) {
                       if (name) *name = st.text(0);
                       return st.text(1);
                   });
}

DatasetRow DatasetStore::row(std::int64_t id) {
    return db_.row(std::string(kSelectDatasets) + " WHERE id = ?", id, NotFound::row("dataset", id), dataset_row);
}

void DatasetStore::remove(std::int64_t id) {
    db_.transaction([&](Database& db) {
        auto del = db.prepare("DELETE FROM datasets WHERE id = ?");
        del.bind_all(id);
        del.run();
        if (db.changes() == 0) throw NotFound::row("dataset", id);
    });
}

json DatasetStore::page(const PageRequest& page, const std::function<json(const DatasetRow&)>& to_json) {
    return db_.with([&](Database& db) {
        return read_page(db, page, "datasets", kSelectDatasets, "id", [&](Statement& st) { return to_json(dataset_row(st)); });
    });
}

std::vector<std::int64_t> DatasetStore::ids_without_header() {
    return db_.with([&](Database& db) {
        std::vector<std::int64_t> ids;
        auto st = db.prepare("SELECT id FROM datasets WHERE header_json IS NULL");
        while (st.step()) ids.push_back(st.int64(0));
        return ids;
    });
}

void DatasetStore::set_header(std::int64_t id, const json& header) {
    const auto text = header.dump();
    db_.transaction([&](Database& db) {
        auto up = db.prepare("UPDATE datasets SET header_json = ? WHERE id = ?");
        up.bind_all(text, id);
        up.run();
    });
}

}  // namespace triax::service
