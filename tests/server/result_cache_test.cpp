// The parsed result documents of finished runs (server/runs/result_cache.hpp): the same
// document is handed out again without re-reading, the least recently used goes first.
#include <catch2/catch.hpp>

#include "server/runs/result_cache.hpp"

using triax::service::ResultCache;

TEST_CASE("result cache: hands out the same document, evicts the least recently used", "[server][cache]") {
    ResultCache cache(2);
    CHECK(cache.find(1) == nullptr);
    auto d1 = std::make_shared<const nlohmann::json>(nlohmann::json{{"summary", {{"run_id", 1}}}});
    auto d2 = std::make_shared<const nlohmann::json>(nlohmann::json{{"summary", {{"run_id", 2}}}});
    auto d3 = std::make_shared<const nlohmann::json>(nlohmann::json{{"summary", {{"run_id", 3}}}});
    cache.put(1, d1);
    cache.put(2, d2);
    CHECK(cache.find(1) == d1);  // 1 is now the most recently used
    cache.put(3, d3);            // capacity 2: 2 goes
    CHECK(cache.find(2) == nullptr);
    CHECK(cache.find(1) == d1);
    CHECK(cache.find(3) == d3);
    cache.put(3, d1);  // a second put replaces, never duplicates
    CHECK(cache.find(3) == d1);
    CHECK(cache.find(1) == d1);
}
