// POST /runs, GET /runs, GET /runs/{id}, POST /runs/{id}/cancel, POST /runs/{id}/rerun,
// GET /runs/{id}/events (SSE).
// Eigen before httplib: <resolv.h> (through httplib) defines a macro _res that Eigen uses as a name.
#include "engine/protocol/imported_packing.hpp"
#include "server/io/scheme_json.hpp"
#include "server/http/problem.hpp"
#include "server/http/sse.hpp"
#include "server/service.hpp"

#include <cstdint>

namespace triax::service {

using nlohmann::json;

void register_run_routes(Service& s) {
    s.route("POST", "/runs", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto body = parse_body(req);
        if (!body.is_object()) throw unprocessable("the body must be an object with 'scheme' or 'scheme_id'").at_field("");
        for (const auto& [k, v] : body.items())
            if (k != "scheme" && k != "scheme_id" && k != "threads" && k != "packing_id")
                throw unprocessable("unknown field '" + k + "' (scheme, scheme_id, threads, packing_id)").at_field("/" + k);
        const bool inline_scheme = body.contains("scheme"), by_id = body.contains("scheme_id");
        if (inline_scheme == by_id) throw unprocessable("give exactly one of 'scheme' or 'scheme_id'").at_field("/scheme");
        std::optional<int> threads;
        if (body.contains("threads")) {
            threads = static_cast<int>(body_integer(body["threads"], "/threads", 1, s.config.max_threads_per_run));
        }
        std::int64_t scheme_id = 0;
        if (by_id) {
            scheme_id = body_integer(body["scheme_id"], "/scheme_id", 1, INT64_MAX);
        } else {
            scheme_id = store_scheme(s, body["scheme"], "/scheme")["id"].get<std::int64_t>();
        }
        std::optional<std::int64_t> packing_id;
        if (body.contains("packing_id")) {
            if (!body["packing_id"].is_number_integer() || body["packing_id"].get<long long>() < 1)
                throw unprocessable("packing_id must be a positive integer").at_field("/packing_id");
            packing_id = body["packing_id"].get<std::int64_t>();
            // The grains must fit this scheme's specimen: refused here, naming the grain's line.
            auto packing = load_packing(s, *packing_id);
            const auto scheme = s.schemes.scheme(scheme_id, "/scheme_id");
            try {
                protocol::validate_packing(packing, io::scheme_from_json(scheme));
            } catch (const InputError& e) {
                throw unprocessable(e.what()).at_field("/packing_id");
            }
        }
        auto out = s.runs.submit(scheme_id, threads, std::nullopt, packing_id);
        if (packing_id) out["packing_id"] = *packing_id;
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
        serve_event_stream(req, res, s.run_events, id, s.event_streams);
    });
}

}  // namespace triax::service
