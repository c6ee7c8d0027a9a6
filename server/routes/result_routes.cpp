// GET /runs/{id}/results/summary and the series (stress-strain, volumetric, creep,
// energies, measurements) with max_points / from / to / stage and ?format=csv.
#include "server/http/problem.hpp"
#include "server/runs/series.hpp"
#include "server/service.hpp"

namespace triax::service {

using nlohmann::json;

namespace {

SeriesQuery parse_query(const httplib::Request& req) {
    SeriesQuery q;
    if (auto v = query_int(req, "max_points", 1, 10'000'000)) q.max_points = static_cast<std::size_t>(*v);
    if (auto v = query_int(req, "stage", 1, 1000)) q.stage = static_cast<int>(*v);
    q.from = query_number(req, "from");
    q.to = query_number(req, "to");
    if (q.from && q.to && *q.from > *q.to) throw unprocessable("'from' must not exceed 'to'").with_limit("from <= to");
    if (req.has_param("format") && req.get_param_value("format") != "csv" && req.get_param_value("format") != "json")
        throw bad_request("format must be 'json' or 'csv'");
    return q;
}

// Stored series when the run is done, else rebuilt from its events so far.
json series_rows(Service& s, std::int64_t id, const SeriesSpec& spec) {
    if (auto doc = s.runs.result(id); doc && doc->contains("series") && doc->at("series").contains(spec.name))
        return doc->at("series").at(spec.name);
    return rows_from_events(spec, s.runs.event_data(id, spec.event_type));
}

void serve_series(Service& s, const httplib::Request& req, httplib::Response& res, const char* name) {
    const auto id = path_id(req);
    const auto& spec = *find_series(name);
    const auto q = parse_query(req);
    s.runs.status(id);  // 404 for an unknown run
    json rows = filter_series(spec, series_rows(s, id, spec), q);
    // Without ?stage the creep series carries all stages with a `stage` column first;
    // with it, the stage column is dropped (docs/api.md).
    std::vector<std::string> columns = spec.columns;
    if (std::string(name) == "creep" && q.stage) {
        columns.erase(columns.begin());
        for (auto& r : rows) r.erase(0);
    }
    if (req.get_param_value("format") == "csv") {
        res.status = 200;
        res.set_content(series_csv(columns, rows), "text/csv");
        return;
    }
    send_json(res, {{"run_id", id}, {"series", name}, {"columns", columns}, {"rows", rows}});
}

}  // namespace

void register_result_routes(Service& s) {
    s.route("GET", R"(/runs/([^/]+)/results/summary)", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto id = path_id(req);
        const auto st = s.runs.status(id);
        const auto doc = s.runs.result(id);
        if (!doc) throw conflict("run " + std::to_string(id) + " is " + st["status"].get<std::string>() +
                                 "; its summary exists once it is done");
        json summary = doc->at("summary");
        summary["run_id"] = id;
        send_json(res, summary);
    });
    const std::pair<const char*, const char*> routes[] = {{"stress-strain", "stress_strain"},
                                                          {"volumetric", "volumetric"},
                                                          {"creep", "creep"},
                                                          {"energies", "energies"},
                                                          {"measurements", "measurements"}};
    for (const auto& [path, name] : routes) {
        const char* series = name;
        s.route("GET", std::string(R"(/runs/([^/]+)/results/)") + path,
                   [&s, series](const httplib::Request& req, httplib::Response& res) { serve_series(s, req, res, series); });
    }
}

}  // namespace triax::service
