#pragma once
// The `datasets` table: lab datasets in their stored form (the JSON upload form, lab units)
// and each one's small header (curve index and summary rows) for listings.
#include "server/http/paging.hpp"
#include "server/http/stored_document.hpp"
#include "server/store/database.hpp"
#include "server/store/not_found.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace triax::service {

struct DatasetRow {
    std::int64_t id = 0;
    std::string name, format, created_at;
    std::optional<nlohmann::json> header;  // absent for rows stored before the column
};

class DatasetStore {
public:
    explicit DatasetStore(Database& db) : db_(db) {}

    std::int64_t insert(const std::string& name, const std::string& format, const std::string& dataset_json,
                        const nlohmann::json& header, const std::string& created_at);
    // The stored dataset's JSON text (and its name into `name` when not null); NotFound.
    std::string dataset_text(std::int64_t id, std::string* name = nullptr);
    DatasetRow row(std::int64_t id);  // NotFound if unknown
    void remove(std::int64_t id);     // NotFound if unknown
    // One page, newest first, each row made JSON by `to_json`; no dataset is parsed.
    nlohmann::json page(const PageRequest& page, const std::function<nlohmann::json(const DatasetRow&)>& to_json);
    // Rows stored without a header, and the header's filling.
    std::vector<std::int64_t> ids_without_header();
    void set_header(std::int64_t id, const nlohmann::json& header);
    // Where the readings are stored, to be sent in slices (http/stored_document.hpp).
    static StoredValue readings(std::int64_t id) { return StoredValue{"datasets", "dataset_json", id}; }

private:
    Database& db_;
};

}  // namespace triax::service
