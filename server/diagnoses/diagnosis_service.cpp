#include "server/diagnoses/diagnosis_service.hpp"

#include "engine/diagnose/diagnosis.hpp"
#include "server/diagnoses/membrane_modulus.hpp"
#include "server/diagnoses/model_schemes.hpp"
#include "server/http/problem.hpp"
#include "server/io/diagnosis_json.hpp"
#include "server/io/scheme_json.hpp"

#include <chrono>
#include <iostream>

namespace triax::service {

using nlohmann::json;

namespace {

const char* kSelectDiagnoses =
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
    StreamingDiagnoseObserver(Database& db, EventLog& events, std::int64_t id, std::function<bool()> cancelled,
                              const protocol::TestScheme& scheme)
        : db_(db), events_(events), id_(id), cancelled_(std::move(cancelled)), scheme_(scheme) {}
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
        auto candidate = io::candidate_to_json(c);
        add_membrane_modulus(candidate["parameters"], scheme_);
        events_.append(id_, "candidate", candidate);
    }
    bool cancelled() const override { return cancelled_(); }

private:
    Database& db_;
    EventLog& events_;
    std::int64_t id_;
    std::function<bool()> cancelled_;
    const protocol::TestScheme& scheme_;
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
    : db_(db), events_(events), load_dataset_(std::move(load_dataset)),
      jobs_(db, queue, JobKind{"diagnosis", "diagnoses", &events, false, "", "re-run it"}, *this) {}

json DiagnosisService::submit(std::int64_t dataset_id, const json& request, std::optional<std::int64_t> rerun_of) {
    const auto id = jobs_.submit([&](Database& db) {
        auto ins = db.prepare(
            "INSERT INTO diagnoses(dataset_id, status, request_json, created_at, rerun_of) VALUES (?, 'queued', ?, ?, ?)");
        ins.bind_all(dataset_id, request.dump(), utc_now(), rerun_of);
        ins.run();
        return db.last_insert_id();
    });
    return {{"id", id}, {"status", "queued"}};
}

json DiagnosisService::rerun(std::int64_t id) {
    jobs_.require_ended(id);
    std::int64_t dataset_id = 0;
    json request;
    db_.with([&](Database& db) {
        auto st = db.prepare("SELECT dataset_id, request_json FROM diagnoses WHERE id = ?");
        st.bind_all(id);
        st.step();
        dataset_id = st.int64(0);
        request = json::parse(st.text(1));
    });
    load_dataset_(dataset_id);  // 404 when the dataset was deleted since
    return submit(dataset_id, request, id);
}

json DiagnosisService::status(std::int64_t id) {
    auto d = db_.with([&](Database& db) {
        auto st = db.prepare(std::string(kSelectDiagnoses) + " WHERE id = ?");
        st.bind_all(id);
        if (!st.step()) throw not_found("diagnosis " + std::to_string(id) + " does not exist");
        // The scheme diagnosed (the user's; the report's model_schemes are the calibrated
        // model's).
        auto out = diagnosis_json(st);
        out["scheme"] = io::without_retired_fields(json::parse(st.text(8)).value("scheme", json(nullptr)));
        return out;
    });
    // K_m as the scheme's membrane modulus, with the scheme diagnosed (accepted, so it parses).
    if (d["report"].is_object() && d["scheme"].is_object())
        add_membrane_modulus_to_report(d["report"], io::scheme_from_json(d["scheme"]));
    return d;
}

json DiagnosisService::list(const PageRequest& page) {
    return db_.with([&](Database& db) {
        return read_page(
            db, page, "diagnoses", kSelectDiagnoses, "id",
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

JobWork::StoreResult DiagnosisService::run(std::int64_t id, const std::function<bool()>& cancelled) {
    json request;
    std::int64_t dataset_id = 0;
    db_.with([&](Database& db) {
        auto q = db.prepare("SELECT request_json, dataset_id FROM diagnoses WHERE id = ?");
        q.bind_all(id);
        q.step();
        request = json::parse(q.text(0));
        dataset_id = q.int64(1);
    });
    const auto lab = load_dataset_(dataset_id);
    const auto scheme = io::scheme_from_json(request["scheme"]);
    const auto options = io::diagnose_options_from_json(request["options"]);
    StreamingDiagnoseObserver observer(db_, events_, id, cancelled, scheme);
    json doc = remote_ ? remote_(id, request, lab, observer)
                       : io::diagnosis_report_to_json(diagnose::run_diagnosis(lab, scheme, options, observer));
    add_model_schemes(doc, scheme, lab, options);
    return [id, report = doc.dump()](Database& db) {
        auto up = db.prepare("UPDATE diagnoses SET report_json = ?, progress_pct = 100 WHERE id = ?");
        up.bind_all(report, id);
        up.run();
    };
}

}  // namespace triax::service
