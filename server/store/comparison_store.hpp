#pragma once
// The `comparisons` table: a run's series against a lab dataset (metrics and residuals).
// Documents come back with their row's id, run_id, dataset_id and created_at merged in.
#include "server/http/paging.hpp"
#include "server/store/database.hpp"
#include "server/store/not_found.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

namespace triax::service {

class ComparisonStore {
public:
    explicit ComparisonStore(Database& db) : db_(db) {}

    std::int64_t insert(std::int64_t run_id, std::int64_t dataset_id, const nlohmann::json& result,
                        const std::string& created_at);
    nlohmann::json get(std::int64_t id);  // NotFound if unknown
    // One page, newest first, each curve without its residuals (the listing has metrics only).
    nlohmann::json page(const PageRequest& page);

private:
    Database& db_;
};

}  // namespace triax::service
