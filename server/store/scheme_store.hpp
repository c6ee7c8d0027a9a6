#pragma once
// The `schemes` table: validated scheme documents (normalised JSON) by id.
#include "server/http/paging.hpp"
#include "server/store/database.hpp"
#include "server/store/not_found.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

namespace triax::service {

class SchemeStore {
public:
    explicit SchemeStore(Database& db) : db_(db) {}

    std::int64_t insert(const std::string& name, const nlohmann::json& scheme);
    // {"id","name","scheme","created_at"}; NotFound if unknown.
    nlohmann::json get(std::int64_t id);
    // The stored scheme document; NotFound (naming `field`, the request member that gave
    // the id) if unknown.
    nlohmann::json scheme(std::int64_t id, const std::string& field = "");
    // The scheme's name, inside the caller's transaction (a job stored with it); NotFound
    // (naming `field`) if unknown.
    static std::string name_in(Database& tx, std::int64_t id, const std::string& field = "");
    // One page of {"id","name","created_at"}, newest first.
    nlohmann::json page(const PageRequest& page);

private:
    Database& db_;
};

}  // namespace triax::service
