#pragma once
// The `packings` table: imported grain packings (the project JSON form) by id.
#include "server/store/database.hpp"
#include "server/store/not_found.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

namespace triax::service {

class PackingStore {
public:
    explicit PackingStore(Database& db) : db_(db) {}

    // Returns the new id; `created_at` is the caller's timestamp (it answers with it).
    std::int64_t insert(const std::string& name, const std::string& format, std::int64_t grains,
                        const nlohmann::json& packing, const std::string& created_at);
    // {"id","name","format","grains","created_at","packing"}; NotFound if unknown.
    nlohmann::json get(std::int64_t id);
    // The stored project JSON; NotFound (naming `field`) if unknown.
    nlohmann::json packing(std::int64_t id, const std::string& field = "");

private:
    Database& db_;
};

}  // namespace triax::service
