// POST /datasets/{id}/diagnose, GET /diagnoses, GET /diagnoses/{id},
// POST /diagnoses/{id}/cancel, POST /diagnoses/{id}/rerun, GET /diagnoses/{id}/events
// (SSE: status, progress, candidate, done, error). The handlers parse and validate; the
// job lifecycle is DiagnosisService's (server/diagnoses).
#include <algorithm>

#include "server/http/paging.hpp"
#include "server/http/problem.hpp"
#include "server/http/sse.hpp"
#include "server/io/diagnosis_json.hpp"
#include "server/io/lab_format.hpp"
#include "server/io/scheme_json.hpp"
#include "server/service.hpp"


namespace triax::service {

using nlohmann::json;

void register_diagnosis_routes(Service& s) {
    s.route("POST", R"(/datasets/([^/]+)/diagnose)", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto dataset_id = path_id(req);
        load_dataset(s, dataset_id, nullptr);  // 404 early
        const auto body = parse_body(req);
        if (!body.is_object()) throw unprocessable("the body must be a JSON object").at_field("");
        const bool inline_scheme = body.contains("scheme"), by_id = body.contains("scheme_id");
        if (inline_scheme == by_id) throw unprocessable("give exactly one of 'scheme' or 'scheme_id'").at_field("/scheme");
        json scheme;
        if (inline_scheme) {
            scheme = store_scheme(s, body["scheme"], "/scheme")["scheme"];
        } else {
            if (!body["scheme_id"].is_number_integer()) throw unprocessable("scheme_id must be an integer").at_field("/scheme_id");
            scheme = s.db.with([&](Database& db) {
                auto st = db.prepare("SELECT scheme_json FROM schemes WHERE id = ?");
                st.bind_all(body["scheme_id"].get<std::int64_t>());
                if (!st.step()) throw not_found("scheme does not exist").at_field("/scheme_id");
                return json::parse(st.text(0));
            });
        }
        json options = body;
        options.erase("scheme");
        options.erase("scheme_id");
        try {
            auto opts = io::diagnose_options_from_json(body);
            // Unless the request sets it, a diagnosis runs the default number of DEM runs at
            // once, or as many as the machine's threads allow; the stored options record it.
            if (!body.contains("concurrency")) {
                opts.concurrency = std::clamp(s.config.max_threads_per_run / opts.threads_per_run, 1, opts.concurrency);
                options["concurrency"] = opts.concurrency;
            }
            // A diagnosis occupies one worker but may run `concurrency` DEM runs of
            // `threads_per_run` threads each: keep that within the machine.
            const int threads = opts.concurrency * opts.threads_per_run;
            if (threads > s.config.max_threads_per_run)
                throw unprocessable("concurrency x threads_per_run = " + std::to_string(threads) + " exceeds " +
                                    std::to_string(s.config.max_threads_per_run) + " threads")
                    .at_field("/concurrency")
                    .with_limit("concurrency * threads_per_run <= " + std::to_string(s.config.max_threads_per_run));
        } catch (const io::DiagnosisRequestError& e) {
            throw unprocessable(e.what()).at_field(e.field);
        }
        const json request{{"scheme", scheme}, {"options", options}};
        const auto out = s.diagnoses.submit(dataset_id, request);
        res.set_header("Location", "/diagnoses/" + std::to_string(out["id"].get<std::int64_t>()));
        send_json(res, out, 202);
    });
    s.route("GET", "/diagnoses", [&s](const httplib::Request& req, httplib::Response& res) {
        send_json(res, s.diagnoses.list(page_request(req, true)));
    });
    s.route("GET", R"(/diagnoses/([^/]+))", [&s](const httplib::Request& req, httplib::Response& res) {
        send_json(res, s.diagnoses.status(path_id(req)));
    });
    s.route("POST", R"(/diagnoses/([^/]+)/cancel)", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto id = path_id(req);
        s.diagnoses.cancel(id);
        send_json(res, {{"id", id}, {"status", "cancelling"}}, 202);
    });
    s.route("POST", R"(/diagnoses/([^/]+)/rerun)", [&s](const httplib::Request& req, httplib::Response& res) {
        auto out = s.diagnoses.rerun(path_id(req));
        out["rerun_of"] = path_id(req);
        res.set_header("Location", "/diagnoses/" + std::to_string(out["id"].get<std::int64_t>()));
        send_json(res, out, 202);
    });
    s.route("GET", R"(/diagnoses/([^/]+)/events)", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto id = path_id(req);
        if (!s.diagnoses.exists(id)) throw not_found("diagnosis " + std::to_string(id) + " does not exist");
        serve_event_stream(req, res, s.diagnosis_events, id, s.event_streams);
    });
}

}  // namespace triax::service
