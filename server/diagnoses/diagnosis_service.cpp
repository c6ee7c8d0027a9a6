#include "server/diagnoses/diagnosis_service.hpp"

#include "engine/diagnose/diagnosis.hpp"
#include "server/diagnoses/model_schemes.hpp"
#include "server/http/problem.hpp"
#include "server/io/diagnosis_json.hpp"
#include "server/io/scheme_json.hpp"

#include <chrono>
#include <iostream>

namespace triax::service {

using nlohmann::json;

namespace {

bool terminal(const std::string& status) {
    return status == "done" || status == "failed" || status == "cancelled" || status == "interrupted";
}

const char* kSelect =
    "SELECT id, dataset_id, status, progress_pct, report_json, created_at, finished_at, error, request_json, rerun_of "
    "FROM diagnoses";

json diagnosis_json(Statement& st) {
    json out{{"id", st.int64(0)},
             {"dataset_id", st.int64(1)},
             {"status", st.text(2)},
             {"progress_pct", st.real(3)},
             {"created_at", st.text(5)},
             {"finished_at", st.is_null(6) ? json(nullptr) : json(st.text(6))},
             {"error", st.is_null(7) ? json(nullptr) : json(st.text(7))},
             {"rerun_of", st.is_null(9) ? json(nullptr) : json(st.int64(9))}};
    out["report"] = st.is_null(4) ? json(nullptr) : json::parse(st.text(4));
    // The options as the diagnosis reads them (the request was validated when it was
    // accepted, so this parse does not throw).
    out["options"] = io::diagnose_options_to_json(io::diagnose_options_from_json(json::parse(st.text(8)).at("options")));
    return out;
}

class StreamingDiagnoseObserver : public diagnose::DiagnoseObserver {
public:
    StreamingDiagnoseObserver(Database& db, EventLog& events, std::int64_t id, std::shared_ptr<std::atomic<bool>> cancel)
        : db_(db), events_(events), id_(id), cancel_(std::move(cancel)) {}
    void on_progress(double percent, std::string_view stage) override {
        const auto now = std::chrono::steady_clock::now();
        if (now - last_ < std::chrono::milliseconds(250) && percent < 100.0) return;
        last_ = now;
        db_.transaction([&](Database& db) {
            events_.append_in(db, id_, "progress", {{"progress_pct", percent}, {"stage", std::string(stage)}});
            auto up = db.prepare("UPDATE diagnoses SET progress_pct = ? WHERE id = ?");
            up.bind_all(percent, id_);
            up.run();
        });
        events_.notify();
    }
    void on_candidate(const diagnose::CandidateResult& c) override {
        events_.append(id_, "candidate", io::candidate_to_json(c));
    }
    bool cancelled() const override { return cancel_->load(); }

private:
    Database& db_;
    EventLog& events_;
    std::int64_t id_;
    std::shared_ptr<std::atomic<bool>> cancel_;
    std::chrono::steady_clock::time_point last_{};
};

// The final model's schemes (model_schemes.hpp) into the report. A report they cannot be
// built for is stored without them: the diagnosis itself succeeded, and the page falls
// back to the scheme diagnosed with the fitted values.
void add_model_schemes(json& report, const protocol::TestScheme& scheme, const diagnose::LabDataset& lab,
                       const diagnose::DiagnoseOptions& options) {
    try {
        report["model_schemes"] = model_schemes_json(scheme, lab, options, io::diagnosis_report_from_json(report));
    } catch (const std::exception& e) {
        std::cerr << "triaxd: the diagnosis's model schemes could not be built: " << e.what() << "\n";
    }
}

}  // namespace

DiagnosisService::DiagnosisService(Database& db, EventLog& events, JobQueue& queue,
                                   std::function<diagnose::LabDataset(std::int64_t)> load_dataset)
    : db_(db), events_(events), queue_(queue), load_dataset_(std::move(load_dataset)) {}

void DiagnosisService::finish(std::int64_t id, const std::string& status, const std::string& detail,
                              const json* report) {
    db_.transaction([&](Database& db) {
        auto up = db.prepare(
            "UPDATE diagnoses SET status = ?, error = ?, report_json = ?, finished_at = ?, progress_pct = "
            "CASE WHEN ? = 'done' THEN 100 ELSE progress_pct END WHERE id = ? AND status IN ('queued', 'running')");
        up.bind_all(status, report ? std::optional<std::string>() : std::optional<std::string>(detail),
                    report ? std::optional<std::string>(report->dump()) : std::optional<std::string>(), utc_now(),
                    status, id);
        up.run();
        if (db.changes() == 0) return;
        if (report) events_.append_in(db, id, "done", {{"status", "done"}});
        else events_.append_in(db, id, "error", {{"status", status}, {"detail", detail}});
    });
    events_.notify();
    cancel_flags_.forget(id);
}

int DiagnosisService::recover_interrupted() {
    std::vector<std::int64_t> ids;
    db_.with([&](Database& db) {
        auto st = db.prepare("SELECT id FROM diagnoses WHERE status IN ('queued', 'running') ORDER BY id");
        while (st.step()) ids.push_back(st.int64(0));
    });
    for (auto id : ids)
        finish(id, "interrupted", "the service stopped before the diagnosis ended; re-run it", nullptr);
    return static_cast<int>(ids.size());
}

json DiagnosisService::submit(std::int64_t dataset_id, const json& request, std::optional<std::int64_t> rerun_of) {
    const auto id = db_.transaction([&](Database& db) {
        auto ins = db.prepare(
            "INSERT INTO diagnoses(dataset_id, status, request_json, created_at, rerun_of) VALUES (?, 'queued', ?, ?, ?)");
        ins.bind_all(dataset_id, request.dump(), utc_now(), rerun_of);
        ins.run();
        const auto new_id = db.last_insert_id();
        events_.append_in(db, new_id, "status", {{"status", "queued"}});
        return new_id;
    });
    const auto flag = cancel_flags_.arm(id);
    if (!queue_.try_submit("diagnosis:" + std::to_string(id), [this, id, flag] { execute(id, flag); })) {
        db_.transaction([&](Database& db) {
            auto del_ev = db.prepare("DELETE FROM diagnosis_events WHERE diagnosis_id = ?");
            del_ev.bind_all(id);
            del_ev.run();
            auto del = db.prepare("DELETE FROM diagnoses WHERE id = ?");
            del.bind_all(id);
            del.run();
        });
        cancel_flags_.forget(id);
        throw queue_full(queue_);
    }
    return {{"id", id}, {"status", "queued"}};
}

void DiagnosisService::cancel(std::int64_t id) {
    const std::string s = status(id)["status"];
    if (terminal(s)) throw conflict("diagnosis " + std::to_string(id) + " is already " + s);
    cancel_flags_.raise(id);
    if (queue_.withdraw("diagnosis:" + std::to_string(id)))
        finish(id, "cancelled", "cancelled by request before it started", nullptr);
}

json DiagnosisService::rerun(std::int64_t id) {
    std::string state;
    std::int64_t dataset_id = 0;
    json request;
    db_.with([&](Database& db) {
        auto st = db.prepare("SELECT status, dataset_id, request_json FROM diagnoses WHERE id = ?");
        st.bind_all(id);
        if (!st.step()) throw not_found("diagnosis " + std::to_string(id) + " does not exist");
        state = st.text(0);
        dataset_id = st.int64(1);
        request = json::parse(st.text(2));
    });
    if (!terminal(state))
        throw conflict("diagnosis " + std::to_string(id) + " is " + state + "; only a finished diagnosis can be re-run");
    load_dataset_(dataset_id);  // 404 when the dataset was deleted since
    return submit(dataset_id, request, id);
}

json DiagnosisService::status(std::int64_t id) {
    return db_.with([&](Database& db) {
        auto st = db.prepare(std::string(kSelect) + " WHERE id = ?");
        st.bind_all(id);
        if (!st.step()) throw not_found("diagnosis " + std::to_string(id) + " does not exist");
        // The scheme diagnosed (the user's; the report's model_schemes are the calibrated
        // model's).
        auto d = diagnosis_json(st);
        d["scheme"] = json::parse(st.text(8)).value("scheme", json(nullptr));
        return d;
    });
}

json DiagnosisService::list(const PageRequest& page) {
    return db_.with([&](Database& db) {
        return read_page(
            db, page, "diagnoses", kSelect, "id",
            [](Statement& st) {
                auto d = diagnosis_json(st);
                if (d["report"].is_object()) d["chosen_effect"] = d["report"].value("chosen_effect", "");
                d.erase("report");
                return d;
            },
            "status");
    });
}

bool DiagnosisService::exists(std::int64_t id) {
    return db_.with([&](Database& db) {
        auto st = db.prepare("SELECT 1 FROM diagnoses WHERE id = ?");
        st.bind_all(id);
        return st.step();
    });
}

void DiagnosisService::begin_shutdown() {
    shutting_down_ = true;
    cancel_flags_.raise_all();
}

void DiagnosisService::execute(std::int64_t id, std::shared_ptr<std::atomic<bool>> cancel) {
    json request;
    std::int64_t dataset_id = 0;
    const bool started = db_.transaction([&](Database& db) {
        auto up = db.prepare("UPDATE diagnoses SET status = 'running' WHERE id = ? AND status = 'queued'");
        up.bind_all(id);
        up.run();
        if (db.changes() == 0) return false;
        auto q = db.prepare("SELECT request_json, dataset_id FROM diagnoses WHERE id = ?");
        q.bind_all(id);
        q.step();
        request = json::parse(q.text(0));
        dataset_id = q.int64(1);
        events_.append_in(db, id, "status", {{"status", "running"}});
        return true;
    });
    events_.notify();
    if (!started) return;
    try {
        const auto lab = load_dataset_(dataset_id);
        const auto scheme = io::scheme_from_json(request["scheme"]);
        const auto options = io::diagnose_options_from_json(request["options"]);
        StreamingDiagnoseObserver observer(db_, events_, id, cancel);
        json doc = remote_ ? remote_(id, request, lab, observer)
                           : io::diagnosis_report_to_json(diagnose::run_diagnosis(lab, scheme, options, observer));
        add_model_schemes(doc, scheme, lab, options);
        finish(id, "done", "", &doc);
    } catch (const diagnose::DiagnosisCancelled&) {
        finish(id, shutting_down_ ? "interrupted" : "cancelled",
               shutting_down_ ? "the service stopped during the diagnosis; re-run it" : "cancelled by request", nullptr);
    } catch (const std::exception& e) {
        finish(id, cancel->load() && shutting_down_ ? "interrupted" : "failed", e.what(), nullptr);
    }
}

}  // namespace triax::service
