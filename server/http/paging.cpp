#include "server/http/paging.hpp"

#include "server/http/problem.hpp"

#include <algorithm>
#include <iterator>
#include <limits>

namespace triax::service {

using nlohmann::json;

namespace {

const char* const kJobStatuses[] = {"queued", "running", "done", "failed", "cancelled", "interrupted"};

std::vector<std::string> status_list(const httplib::Request& req) {
    std::vector<std::string> out;
    if (!req.has_param("status")) return out;
    const std::string all = req.get_param_value("status");
    std::size_t from = 0;
    while (from <= all.size()) {
        const auto comma = std::min(all.find(',', from), all.size());
        const std::string one = all.substr(from, comma - from);
        if (std::find(std::begin(kJobStatuses), std::end(kJobStatuses), one) == std::end(kJobStatuses))
            throw unprocessable("query parameter 'status' has '" + one +
                                "'; give a comma-separated list of queued, running, done, failed, cancelled, "
                                "interrupted")
                .with_limit("status in {queued, running, done, failed, cancelled, interrupted}");
        if (std::find(out.begin(), out.end(), one) == out.end()) out.push_back(one);
        from = comma + 1;
    }
    return out;
}

// " AND col IN (?, ?)" for the status filter, "" without one.
std::string status_clause(const PageRequest& page, const std::string& status_col) {
    if (page.statuses.empty() || status_col.empty()) return "";
    std::string in = " AND " + status_col + " IN (";
    for (std::size_t i = 0; i < page.statuses.size(); ++i) in += i ? ", ?" : "?";
    return in + ")";
}

}  // namespace

PageRequest page_request(const httplib::Request& req, bool job_statuses) {
    PageRequest p;
    if (auto v = query_int(req, "limit", 1, kPageLimitMax)) p.limit = *v;
    p.before_id = query_int(req, "before_id", 1, std::numeric_limits<std::int64_t>::max());
    if (job_statuses) p.statuses = status_list(req);
    return p;
}

json read_page(Database& db, const PageRequest& page, const std::string& key, const std::string& select,
               const std::string& id_col, const std::function<json(Statement&)>& row, const std::string& status_col) {
    json items = json::array();
    json next = nullptr;
    const std::string filter = status_clause(page, status_col);
    auto st = db.prepare(select + " WHERE " + id_col + " < ?" + filter + " ORDER BY " + id_col + " DESC LIMIT ?");
    int at = 1;
    st.bind(at++, page.before_id.value_or(std::numeric_limits<std::int64_t>::max()));
    if (!filter.empty())
        for (const auto& s : page.statuses) st.bind(at++, s);
    st.bind(at++, page.limit + 1);
    std::int64_t last = 0;
    for (std::int64_t n = 0; st.step(); ++n) {
        // One row beyond the page says whether there is a next one.
        if (n == page.limit) {
            next = last;
            break;
        }
        last = st.int64(0);
        items.push_back(row(st));
    }
    const auto from = select.substr(select.find(" FROM "));
    auto count = db.prepare("SELECT COUNT(*)" + from + (filter.empty() ? "" : " WHERE 1" + filter));
    at = 1;
    if (!filter.empty())
        for (const auto& s : page.statuses) count.bind(at++, s);
    count.step();
    return {{key, items}, {"total", count.int64(0)}, {"limit", page.limit}, {"next_before_id", next}};
}

}  // namespace triax::service
