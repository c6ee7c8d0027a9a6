#pragma once
// Paging of the list endpoints (/schemes, /runs, /datasets, /comparisons, /diagnoses):
// newest first by id, `limit` items (default 50, at most 500), and the cursor `before_id`
// (the `next_before_id` of the previous page). Ids only grow, so a page boundary does not
// move when new rows arrive while a client pages (an offset would repeat rows).
#include "server/store/database.hpp"

#include <httplib.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace triax::service {

inline constexpr std::int64_t kPageLimitDefault = 50, kPageLimitMax = 500;

struct PageRequest {
    std::int64_t limit = kPageLimitDefault;
    std::optional<std::int64_t> before_id;
    std::vector<std::string> statuses;  // jobs only (runs, diagnoses): keep these; empty = all
};

// `limit` in [1, 500] (422 naming it), `before_id` >= 1 (400/422 naming it). With
// `job_statuses`, also `status=a,b` (each one of the job states, else 422 naming `status`):
// the activity line asks for `status=queued,running`, which one page always holds, instead
// of reading the whole history every poll.
PageRequest page_request(const httplib::Request& req, bool job_statuses = false);

// One page: `select` is "SELECT <columns> FROM <table> [alias]" with the id column `id_col`
// (also the first column), each row made JSON by `row`; `status_col` is the column the
// request's `statuses` filter (ignored when empty). Answers
// {key: [...], "total": rows matching (the whole list without a filter), "limit": L,
//  "next_before_id": id | null}.
nlohmann::json read_page(Database& db, const PageRequest& page, const std::string& key, const std::string& select,
                         const std::string& id_col, const std::function<nlohmann::json(Statement&)>& row,
                         const std::string& status_col = "");

}  // namespace triax::service
