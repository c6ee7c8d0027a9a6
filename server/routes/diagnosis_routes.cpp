// POST /datasets/{id}/diagnose, POST /datasets/{id}/diagnosis-plan (its runs and minutes,
// starting nothing), GET /diagnoses, GET /diagnoses/{id},
// POST /diagnoses/{id}/cancel, POST /diagnoses/{id}/rerun, GET /diagnoses/{id}/events
// (SSE: status, progress, candidate, done, error). The handlers parse and validate; the
// job lifecycle is DiagnosisService's (server/diagnoses).
#include <algorithm>
#include <stdexcept>

#include "server/diagnoses/diagnosis_plan.hpp"
#include "server/http/paging.hpp"
#include "server/http/problem.hpp"
#include "server/io/bounded_json.hpp"
#include "server/http/sse.hpp"
#include "server/io/diagnosis_json.hpp"
#include "server/io/lab_format.hpp"
#include "server/io/scheme_json.hpp"
#include "server/service.hpp"


namespace triax::service {

using nlohmann::json;

namespace {

// The body of POST /datasets/{id}/diagnose and /diagnosis-plan, checked: the scheme (inline
// or by id), the options with `concurrency` filled in when absent, and the dataset. 404 for
// an unknown dataset or scheme_id, 422 naming the field otherwise.
struct DiagnoseRequest {
    std::int64_t dataset_id = 0;
    diagnose::LabDataset lab;
    json scheme;                   // the scheme document (lab units), as a diagnosis stores it
    protocol::TestScheme parsed;
    json options;                  // the body without the scheme, `concurrency` recorded
    diagnose::DiagnoseOptions opts;
};

// `store_inline`: an inline scheme is stored (a diagnosis refers to it) or only validated
// (the plan starts and stores nothing); the checks are the same.
DiagnoseRequest read_diagnose_request(Service& s, const httplib::Request& req, bool store_inline) {
    DiagnoseRequest r;
    r.dataset_id = path_id(req);
    r.lab = load_dataset(s, r.dataset_id, nullptr);  // 404 early
    const auto body = parse_body(req);
    if (!body.is_object()) throw unprocessable("the body must be a JSON object").at_field("");
    // A misspelt option would otherwise run with its default: refuse what is not an option.
    // The option names are the ones diagnose_options_to_json writes.
    const json known = io::diagnose_options_to_json({});
    for (const auto& [key, value] : body.items())
        if (key != "scheme" && key != "scheme_id" && !known.contains(key)) {
            std::string names = "scheme, scheme_id";
            for (const auto& [k, v] : known.items()) names += ", " + k;
            throw unprocessable("unknown diagnose option '" + key + "'; the body takes " + names)
                .at_field("/" + io::json_pointer_token(key));
        }
    const bool inline_scheme = body.contains("scheme"), by_id = body.contains("scheme_id");
    if (inline_scheme == by_id) throw unprocessable("give exactly one of 'scheme' or 'scheme_id'").at_field("/scheme");
    if (inline_scheme) {
        if (store_inline) {
            r.scheme = store_scheme(s, body["scheme"], "/scheme")["scheme"];
            r.parsed = io::scheme_from_json(r.scheme);
        } else {
            r.parsed = validated_scheme(s, body["scheme"], "/scheme");
            r.scheme = io::scheme_to_json(r.parsed);
        }
    } else {
        if (!body["scheme_id"].is_number_integer()) throw unprocessable("scheme_id must be an integer").at_field("/scheme_id");
        r.scheme = io::without_retired_fields(s.schemes.scheme(body["scheme_id"].get<std::int64_t>(), "/scheme_id"));
        // Stored schemes passed validated_scheme when they were stored.
        r.parsed = io::scheme_from_json(r.scheme);
    }
    r.options = body;
    r.options.erase("scheme");
    r.options.erase("scheme_id");
    try {
        r.opts = io::diagnose_options_from_json(body);
        // Unless the request sets it, a diagnosis runs the default number of DEM runs at
        // once, or as many as the machine's threads allow; the stored options record it.
        if (!body.contains("concurrency")) {
            r.opts.concurrency = std::clamp(s.config.max_threads_per_run / r.opts.threads_per_run, 1, r.opts.concurrency);
            r.options["concurrency"] = r.opts.concurrency;
        }
        // A diagnosis occupies one worker but may run `concurrency` DEM runs of
        // `threads_per_run` threads each: keep that within the machine.
        const int threads = r.opts.concurrency * r.opts.threads_per_run;
        if (threads > s.config.max_threads_per_run)
            throw unprocessable("concurrency x threads_per_run = " + std::to_string(threads) + " exceeds " +
                                std::to_string(s.config.max_threads_per_run) + " threads")
                .at_field("/concurrency")
                .with_limit("concurrency * threads_per_run <= " + std::to_string(s.config.max_threads_per_run));
    } catch (const io::DiagnosisRequestError& e) {
        throw unprocessable(e.what()).at_field(e.field);
    }
    return r;
}

}  // namespace

void register_diagnosis_routes(Service& s) {
    s.route("POST", R"(/datasets/([^/]+)/diagnose)", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto r = read_diagnose_request(s, req, true);
        // What the client started; null when the dataset has no curve a diagnosis can use
        // (the diagnosis then fails with the engine's reason, as POST .../diagnosis-plan says).
        json plan = nullptr;
        try {
            plan = diagnosis_cost_to_json(plan_diagnosis_cost(r.lab, r.parsed, r.opts), r.opts);
        } catch (const std::invalid_argument&) {
            // plan stays null
        }
        auto out = s.diagnoses.submit(r.dataset_id, {{"scheme", r.scheme}, {"options", r.options}});
        out["plan"] = std::move(plan);
        res.set_header("Location", "/diagnoses/" + std::to_string(out["id"].get<std::int64_t>()));
        send_json(res, out, 202);
    });
    s.route("POST", R"(/datasets/([^/]+)/diagnosis-plan)", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto r = read_diagnose_request(s, req, false);
        try {
            send_json(res, diagnosis_cost_to_json(plan_diagnosis_cost(r.lab, r.parsed, r.opts), r.opts));
        } catch (const std::invalid_argument& e) {
            throw unprocessable(e.what());
        }
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
