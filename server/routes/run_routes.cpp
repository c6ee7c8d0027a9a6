// POST /runs, GET /runs, GET /runs/{id}, POST /runs/{id}/cancel, POST /runs/{id}/rerun,
// GET /runs/{id}/events (SSE).
#include "server/http/problem.hpp"
#include "server/http/sse.hpp"
#include "server/service.hpp"

namespace triax::service {

using nlohmann::json;

void register_run_routes(Service& s) {
    s.route("POST", "/runs", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto body = parse_body(req);
        if (!body.is_object()) throw unprocessable("the body must be an object with 'scheme' or 'scheme_id'").at_field("");
        for (const auto& [k, v] : body.items())
            if (k != "scheme" && k != "scheme_id" && k != "threads")
                throw unprocessable("unknown field '" + k + "' (scheme, scheme_id, threads)").at_field("/" + k);
        const bool inline_scheme = body.contains("scheme"), by_id = body.contains("scheme_id");
        if (inline_scheme == by_id) throw unprocessable("give exactly one of 'scheme' or 'scheme_id'").at_field("/scheme");
        std::optional<int> threads;
        if (body.contains("threads")) {
            if (!body["threads"].is_number_integer())
                throw unprocessable("threads must be an integer").at_field("/threads");
            const auto t = body["threads"].get<long long>();
            if (t < 1 || t > s.config.max_threads_per_run)
                throw unprocessable("threads = " + std::to_string(t) + " is outside [1, " +
                                    std::to_string(s.config.max_threads_per_run) + "]")
                    .at_field("/threads")
                    .with_limit("1 <= threads <= " + std::to_string(s.config.max_threads_per_run));
            threads = static_cast<int>(t);
        }
        std::int64_t scheme_id = 0;
        if (by_id) {
            if (!body["scheme_id"].is_number_integer() || body["scheme_id"].get<long long>() < 1)
                throw unprocessable("scheme_id must be a positive integer").at_field("/scheme_id");
            scheme_id = body["scheme_id"].get<std::int64_t>();
        } else {
            scheme_id = store_scheme(s, body["scheme"], "/scheme")["id"].get<std::int64_t>();
        }
        auto out = s.runs.submit(scheme_id, threads);
        out["scheme_id"] = scheme_id;
        res.set_header("Location", "/runs/" + std::to_string(out["id"].get<std::int64_t>()));
        send_json(res, out, 202);
    });
    s.route("GET", "/runs", [&s](const httplib::Request& req, httplib::Response& res) {
        send_json(res, s.runs.list(page_request(req, true)));
    });
    s.route("GET", R"(/runs/([^/]+))", [&s](const httplib::Request& req, httplib::Response& res) {
        send_json(res, s.runs.status(path_id(req)));
    });
    s.route("POST", R"(/runs/([^/]+)/cancel)", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto id = path_id(req);
        s.runs.cancel(id);
        send_json(res, {{"id", id}, {"status", "cancelling"}}, 202);
    });
    s.route("POST", R"(/runs/([^/]+)/rerun)", [&s](const httplib::Request& req, httplib::Response& res) {
        auto out = s.runs.rerun(path_id(req));
        out["rerun_of"] = path_id(req);
        send_json(res, out, 202);
    });
    s.route("GET", R"(/runs/([^/]+)/events)", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto id = path_id(req);
        if (!s.runs.exists(id)) throw not_found("run " + std::to_string(id) + " does not exist");
        serve_event_stream(req, res, s.run_events, id);
    });
}

}  // namespace triax::service
