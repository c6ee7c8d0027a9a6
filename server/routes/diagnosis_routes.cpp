// POST /datasets/{id}/diagnose, GET /diagnoses, GET /diagnoses/{id},
// POST /diagnoses/{id}/cancel, GET /diagnoses/{id}/events (SSE: status, progress,
// candidate, done, error). A diagnosis is a job on the same bounded queue as the runs; it
// calls diagnose::run_diagnosis (engine/diagnose) and stores the report
// (server/io/diagnosis_json) with its event history.
#include "engine/diagnose/diagnosis.hpp"
#include "server/http/paging.hpp"
#include "server/http/problem.hpp"
#include "server/http/sse.hpp"
#include "server/io/diagnosis_json.hpp"
#include "server/io/scheme_json.hpp"
#include "server/service.hpp"

#include <chrono>

namespace triax::service {

using nlohmann::json;

namespace {

void finish_diagnosis(Service& s, std::int64_t id, const std::string& status, const std::string& detail,
                      const json* report) {
    s.db.transaction([&](Database& db) {
        auto up = db.prepare(
            "UPDATE diagnoses SET status = ?, error = ?, report_json = ?, finished_at = ?, progress_pct = "
            "CASE WHEN ? = 'done' THEN 100 ELSE progress_pct END WHERE id = ? AND status IN ('queued', 'running')");
        up.bind_all(status, report ? std::optional<std::string>() : std::optional<std::string>(detail),
                    report ? std::optional<std::string>(report->dump()) : std::optional<std::string>(), utc_now(),
                    status, id);
        up.run();
        if (db.changes() == 0) return;
        if (report) s.diagnosis_events.append_in(db, id, "done", {{"status", "done"}});
        else s.diagnosis_events.append_in(db, id, "error", {{"status", status}, {"detail", detail}});
    });
    s.diagnosis_events.notify();
    std::lock_guard lock(s.diagnosis_mutex);
    s.diagnosis_cancel.erase(id);
}

class StreamingDiagnoseObserver : public diagnose::DiagnoseObserver {
public:
    StreamingDiagnoseObserver(Service& s, std::int64_t id, std::shared_ptr<std::atomic<bool>> cancel)
        : s_(s), id_(id), cancel_(std::move(cancel)) {}
    void on_progress(double percent, std::string_view stage) override {
        const auto now = std::chrono::steady_clock::now();
        if (now - last_ < std::chrono::milliseconds(250) && percent < 100.0) return;
        last_ = now;
        s_.db.transaction([&](Database& db) {
            s_.diagnosis_events.append_in(db, id_, "progress", {{"progress_pct", percent}, {"stage", std::string(stage)}});
            auto up = db.prepare("UPDATE diagnoses SET progress_pct = ? WHERE id = ?");
            up.bind_all(percent, id_);
            up.run();
        });
        s_.diagnosis_events.notify();
    }
    void on_candidate(const diagnose::CandidateResult& c) override {
        s_.diagnosis_events.append(id_, "candidate", io::candidate_to_json(c));
    }
    bool cancelled() const override { return cancel_->load(); }

private:
    Service& s_;
    std::int64_t id_;
    std::shared_ptr<std::atomic<bool>> cancel_;
    std::chrono::steady_clock::time_point last_{};
};

void execute_diagnosis(Service& s, std::int64_t id, std::shared_ptr<std::atomic<bool>> cancel) {
    json request;
    std::int64_t dataset_id = 0;
    const bool started = s.db.transaction([&](Database& db) {
        auto up = db.prepare("UPDATE diagnoses SET status = 'running' WHERE id = ? AND status = 'queued'");
        up.bind_all(id);
        up.run();
        if (db.changes() == 0) return false;
        auto q = db.prepare("SELECT request_json, dataset_id FROM diagnoses WHERE id = ?");
        q.bind_all(id);
        q.step();
        request = json::parse(q.text(0));
        dataset_id = q.int64(1);
        s.diagnosis_events.append_in(db, id, "status", {{"status", "running"}});
        return true;
    });
    s.diagnosis_events.notify();
    if (!started) return;
    try {
        const auto lab = load_dataset(s, dataset_id, nullptr);
        const auto scheme = io::scheme_from_json(request["scheme"]);
        const auto options = io::diagnose_options_from_json(request["options"]);
        StreamingDiagnoseObserver observer(s, id, cancel);
        const auto report = diagnose::run_diagnosis(lab, scheme, options, observer);
        const json doc = io::diagnosis_report_to_json(report);
        finish_diagnosis(s, id, "done", "", &doc);
    } catch (const diagnose::DiagnosisCancelled&) {
        finish_diagnosis(s, id, s.shutting_down ? "interrupted" : "cancelled",
                         s.shutting_down ? "the service stopped during the diagnosis; start it again" : "cancelled by request",
                         nullptr);
    } catch (const std::exception& e) {
        finish_diagnosis(s, id, "failed", e.what(), nullptr);
    }
}

json diagnosis_json(Statement& st) {
    json out{{"id", st.int64(0)},
             {"dataset_id", st.int64(1)},
             {"status", st.text(2)},
             {"progress_pct", st.real(3)},
             {"created_at", st.text(5)},
             {"finished_at", st.is_null(6) ? json(nullptr) : json(st.text(6))},
             {"error", st.is_null(7) ? json(nullptr) : json(st.text(7))}};
    out["report"] = st.is_null(4) ? json(nullptr) : json::parse(st.text(4));
    // The options as the diagnosis reads them (the request was validated when it was
    // accepted, so this parse does not throw).
    out["options"] = io::diagnose_options_to_json(io::diagnose_options_from_json(json::parse(st.text(8)).at("options")));
    return out;
}

const char* kSelect =
    "SELECT id, dataset_id, status, progress_pct, report_json, created_at, finished_at, error, request_json "
    "FROM diagnoses";

}  // namespace

int recover_interrupted_diagnoses(Service& s) {
    std::vector<std::int64_t> ids;
    s.db.with([&](Database& db) {
        auto st = db.prepare("SELECT id FROM diagnoses WHERE status IN ('queued', 'running')");
        while (st.step()) ids.push_back(st.int64(0));
    });
    for (auto id : ids) finish_diagnosis(s, id, "interrupted", "the service stopped before the diagnosis ended", nullptr);
    return static_cast<int>(ids.size());
}

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
        try {
            const auto opts = io::diagnose_options_from_json(body);
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
        json options = body;
        options.erase("scheme");
        options.erase("scheme_id");
        const json request{{"scheme", scheme}, {"options", options}};
        const auto id = s.db.transaction([&](Database& db) {
            auto ins = db.prepare(
                "INSERT INTO diagnoses(dataset_id, status, request_json, created_at) VALUES (?, 'queued', ?, ?)");
            ins.bind_all(dataset_id, request.dump(), utc_now());
            ins.run();
            const auto new_id = db.last_insert_id();
            s.diagnosis_events.append_in(db, new_id, "status", {{"status", "queued"}});
            return new_id;
        });
        auto flag = std::make_shared<std::atomic<bool>>(false);
        {
            std::lock_guard lock(s.diagnosis_mutex);
            s.diagnosis_cancel[id] = flag;
        }
        if (!s.queue.try_submit("diagnosis:" + std::to_string(id), [&s, id, flag] { execute_diagnosis(s, id, flag); })) {
            s.db.transaction([&](Database& db) {
                auto del = db.prepare("DELETE FROM diagnoses WHERE id = ?");
                del.bind_all(id);
                del.run();
            });
            throw ApiError(429, "Too Many Requests", "the job queue is full; retry later")
                .with_limit("queue_limit = " + std::to_string(s.queue.limit()));
        }
        res.set_header("Location", "/diagnoses/" + std::to_string(id));
        send_json(res, {{"id", id}, {"status", "queued"}}, 202);
    });
    s.route("GET", "/diagnoses", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto page = page_request(req, true);
        send_json(res, s.db.with([&](Database& db) {
            return read_page(
                db, page, "diagnoses", kSelect, "id",
                [](Statement& st) {
                    auto d = diagnosis_json(st);
                    if (d["report"].is_object()) d["chosen_effect"] = d["report"].value("chosen_effect", "");
                    d.erase("report");
                    return d;
                },
                "status");
        }));
    });
    s.route("GET", R"(/diagnoses/([^/]+))", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto id = path_id(req);
        send_json(res, s.db.with([&](Database& db) {
            auto st = db.prepare(std::string(kSelect) + " WHERE id = ?");
            st.bind_all(id);
            if (!st.step()) throw not_found("diagnosis " + std::to_string(id) + " does not exist");
            return diagnosis_json(st);
        }));
    });
    s.route("POST", R"(/diagnoses/([^/]+)/cancel)", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto id = path_id(req);
        const auto status = s.db.with([&](Database& db) {
            auto st = db.prepare("SELECT status FROM diagnoses WHERE id = ?");
            st.bind_all(id);
            if (!st.step()) throw not_found("diagnosis " + std::to_string(id) + " does not exist");
            return st.text(0);
        });
        if (status != "queued" && status != "running") throw conflict("diagnosis " + std::to_string(id) + " is already " + status);
        {
            std::lock_guard lock(s.diagnosis_mutex);
            if (auto it = s.diagnosis_cancel.find(id); it != s.diagnosis_cancel.end()) it->second->store(true);
        }
        if (s.queue.withdraw("diagnosis:" + std::to_string(id)))
            finish_diagnosis(s, id, "cancelled", "cancelled by request before it started", nullptr);
        send_json(res, {{"id", id}, {"status", "cancelling"}}, 202);
    });
    s.route("GET", R"(/diagnoses/([^/]+)/events)", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto id = path_id(req);
        const bool exists = s.db.with([&](Database& db) {
            auto st = db.prepare("SELECT 1 FROM diagnoses WHERE id = ?");
            st.bind_all(id);
            return st.step();
        });
        if (!exists) throw not_found("diagnosis " + std::to_string(id) + " does not exist");
        serve_event_stream(req, res, s.diagnosis_events, id);
    });
}

}  // namespace triax::service
