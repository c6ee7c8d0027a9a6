#include "server/http/paging.hpp"

#include "server/http/problem.hpp"

#include <limits>

namespace triax::service {

using nlohmann::json;

PageRequest page_request(const httplib::Request& req) {
    PageRequest p;
    if (auto v = query_int(req, "limit", 1, kPageLimitMax)) p.limit = *v;
    p.before_id = query_int(req, "before_id", 1, std::numeric_limits<std::int64_t>::max());
    return p;
}

json read_page(Database& db, const PageRequest& page, const std::string& key, const std::string& select,
               const std::string& id_col, const std::function<json(Statement&)>& row) {
    json items = json::array();
    json next = nullptr;
    auto st = db.prepare(select + " WHERE " + id_col + " < ? ORDER BY " + id_col + " DESC LIMIT ?");
    st.bind_all(page.before_id.value_or(std::numeric_limits<std::int64_t>::max()), page.limit + 1);
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
    auto count = db.prepare("SELECT COUNT(*)" + from);
    count.step();
    return {{key, items}, {"total", count.int64(0)}, {"limit", page.limit}, {"next_before_id", next}};
}

}  // namespace triax::service
