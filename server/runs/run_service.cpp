#include "server/runs/run_service.hpp"

#include "server/http/problem.hpp"

#include <chrono>

namespace triax::service {

using nlohmann::json;

namespace {

const char* kStatusColumns =
    "SELECT r.id, r.scheme_id, r.name, r.status, r.stage, r.progress_pct, r.eta_s, r.created_at, r.started_at, "
    "r.finished_at, r.error, r.threads, r.rerun_of FROM runs r";

json status_row(Statement& st) {
    auto opt_text = [&](int c) { return st.is_null(c) ? json(nullptr) : json(st.text(c)); };
    auto opt_real = [&](int c) { return st.is_null(c) ? json(nullptr) : json(st.real(c)); };
    return {{"id", st.int64(0)},          {"scheme_id", st.int64(1)},    {"name", st.text(2)},
            {"status", st.text(3)},       {"stage", opt_text(4)},        {"progress_pct", st.real(5)},
            {"eta_s", opt_real(6)},       {"created_at", st.text(7)},    {"started_at", opt_text(8)},
            {"finished_at", opt_text(9)}, {"error", opt_text(10)},       {"threads", st.int64(11)},
            {"rerun_of", st.is_null(12) ? json(nullptr) : json(st.int64(12))}};
}

bool terminal(const std::string& status) {
    return status == "done" || status == "failed" || status == "cancelled" || status == "interrupted";
}

}  // namespace

RunService::RunService(Database& db, EventLog& events, JobQueue& queue, RunExecutor executor, int default_threads,
                       int max_threads)
    : db_(db), events_(events), queue_(queue), executor_(std::move(executor)), default_threads_(default_threads),
      max_threads_(max_threads) {}

int RunService::recover_interrupted() {
    std::vector<std::int64_t> ids;
    db_.with([&](Database& db) {
        auto st = db.prepare("SELECT id FROM runs WHERE status IN ('queued', 'running') ORDER BY id");
        while (st.step()) ids.push_back(st.int64(0));
    });
    for (auto id : ids) finish(id, "interrupted", "the service stopped before the run ended; re-run it");
    return static_cast<int>(ids.size());
}

json RunService::submit(std::int64_t scheme_id, std::optional<int> threads, std::optional<std::int64_t> rerun_of,
                        std::optional<std::int64_t> packing_id) {
    const int n_threads = threads.value_or(default_threads_);
    if (n_threads < 1 || n_threads > max_threads_)
        throw unprocessable("threads = " + std::to_string(n_threads) + " is outside [1, " + std::to_string(max_threads_) +
                            "]")
            .at_field("/threads")
            .with_limit("1 <= threads <= " + std::to_string(max_threads_));
    const auto id = db_.transaction([&](Database& db) {
        auto name = db.prepare("SELECT name FROM schemes WHERE id = ?");
        name.bind_all(scheme_id);
        if (!name.step()) throw not_found("scheme " + std::to_string(scheme_id) + " does not exist").at_field("/scheme_id");
        if (packing_id) {
            auto pk = db.prepare("SELECT 1 FROM packings WHERE id = ?");
            pk.bind_all(*packing_id);
            if (!pk.step()) throw not_found("packing " + std::to_string(*packing_id) + " does not exist").at_field("/packing_id");
        }
        auto ins = db.prepare(
            "INSERT INTO runs(scheme_id, name, status, threads, rerun_of, created_at, packing_id) VALUES (?, ?, 'queued', ?, ?, ?, ?)");
        ins.bind_all(scheme_id, name.text(0), n_threads, rerun_of, utc_now(), packing_id);
        ins.run();
        const auto run_id = db.last_insert_id();
        events_.append_in(db, run_id, "status", {{"status", "queued"}});
        return run_id;
    });
    const auto flag = cancel_flags_.arm(id);
    if (!queue_.try_submit("run:" + std::to_string(id), [this, id, flag] { execute(id, flag); })) {
        // Nothing of a refused run is kept: the client was told 429 and will retry.
        db_.transaction([&](Database& db) {
            auto del_ev = db.prepare("DELETE FROM run_events WHERE run_id = ?");
            del_ev.bind_all(id);
            del_ev.run();
            auto del = db.prepare("DELETE FROM runs WHERE id = ?");
            del.bind_all(id);
            del.run();
        });
        cancel_flags_.forget(id);
        throw queue_full(queue_, "the run queue is full (" + std::to_string(queue_.limit()) + " waiting runs); retry later");
    }
    return {{"id", id}, {"status", "queued"}};
}

void RunService::cancel(std::int64_t id) {
    const auto st = status(id);
    const std::string s = st["status"];
    if (terminal(s)) throw conflict("run " + std::to_string(id) + " is already " + s);
    cancel_flags_.raise(id);
    if (queue_.withdraw("run:" + std::to_string(id))) finish(id, "cancelled", "cancelled by request before it started");
}

json RunService::rerun(std::int64_t id) {
    const auto st = status(id);
    const std::string s = st["status"];
    if (!terminal(s)) throw conflict("run " + std::to_string(id) + " is " + s + "; only a finished run can be re-run");
    const auto packing_id = db_.with([&](Database& db) {
        auto q = db.prepare("SELECT packing_id FROM runs WHERE id = ?");
        q.bind_all(id);
        q.step();
        return q.is_null(0) ? std::optional<std::int64_t>() : std::optional<std::int64_t>(q.int64(0));
    });
    return submit(st["scheme_id"].get<std::int64_t>(), st["threads"].get<int>(), id, packing_id);
}

json RunService::status(std::int64_t id) {
    return db_.with([&](Database& db) {
        auto st = db.prepare(std::string(kStatusColumns) + " WHERE r.id = ?");
        st.bind_all(id);
        if (!st.step()) throw not_found("run " + std::to_string(id) + " does not exist");
        return status_row(st);
    });
}

bool RunService::exists(std::int64_t id) {
    return db_.with([&](Database& db) {
        auto st = db.prepare("SELECT 1 FROM runs WHERE id = ?");
        st.bind_all(id);
        return st.step();
    });
}

json RunService::list(const PageRequest& page) {
    return db_.with([&](Database& db) { return read_page(db, page, "runs", kStatusColumns, "r.id", status_row, "r.status"); });
}

ResultCache::Document RunService::result(std::int64_t id) {
    if (auto doc = results_.find(id)) return doc;
    auto doc = db_.with([&](Database& db) -> ResultCache::Document {
        auto st = db.prepare("SELECT result_json FROM run_results WHERE run_id = ?");
        st.bind_all(id);
        if (!st.step()) return nullptr;
        return std::make_shared<const json>(json::parse(st.text(0)));
    });
    if (doc) results_.put(id, doc);  // written once when the run ended: never stale
    return doc;
}

std::vector<json> RunService::event_data(std::int64_t id, const std::string& type) {
    return db_.with([&](Database& db) {
        std::vector<json> out;
        auto st = db.prepare("SELECT data FROM run_events WHERE run_id = ? AND type = ? ORDER BY seq");
        st.bind_all(id, type);
        while (st.step()) out.push_back(json::parse(st.text(0)));
        return out;
    });
}

json RunService::snapshots(std::int64_t id) {
    return db_.with([&](Database& db) {
        json items = json::array();
        auto st = db.prepare(
            "SELECT stage, grains, membrane_particles, contacts FROM run_snapshots WHERE run_id = ? ORDER BY seq");
        st.bind_all(id);
        while (st.step())
            items.push_back({{"stage", st.text(0)},
                             {"grains", st.int64(1)},
                             {"membrane_particles", st.int64(2)},
                             {"contacts", st.int64(3)}});
        return items;
    });
}

std::optional<std::string> RunService::snapshot_bytes(std::int64_t id, const std::string& stage) {
    return db_.with([&](Database& db) -> std::optional<std::string> {
        auto st = db.prepare("SELECT data FROM run_snapshots WHERE run_id = ? AND stage = ?");
        st.bind_all(id, stage);
        if (!st.step()) return std::nullopt;
        return st.blob(0);
    });
}

void RunService::finish(std::int64_t id, const std::string& status, const std::string& detail) {
    db_.transaction([&](Database& db) {
        auto up = db.prepare(
            "UPDATE runs SET status = ?, error = ?, finished_at = ?, eta_s = NULL WHERE id = ? AND status IN "
            "('queued', 'running')");
        up.bind_all(status, status == "done" ? std::optional<std::string>() : std::optional<std::string>(detail),
                    utc_now(), id);
        up.run();
        if (db.changes() == 0) return;  // already finished by someone else
        events_.append_in(db, id, "error", {{"status", status}, {"detail", detail}});
    });
    events_.notify();
    cancel_flags_.forget(id);
}

void RunService::execute(std::int64_t id, std::shared_ptr<std::atomic<bool>> cancel) {
    json scheme, packing;
    int threads = 1;
    const bool started = db_.transaction([&](Database& db) {
        auto up = db.prepare("UPDATE runs SET status = 'running', started_at = ? WHERE id = ? AND status = 'queued'");
        up.bind_all(utc_now(), id);
        up.run();
        if (db.changes() == 0) return false;
        auto q = db.prepare(
            "SELECT s.scheme_json, r.threads, p.packing_json FROM runs r JOIN schemes s ON s.id = r.scheme_id "
            "LEFT JOIN packings p ON p.id = r.packing_id WHERE r.id = ?");
        q.bind_all(id);
        q.step();
        scheme = json::parse(q.text(0));
        threads = static_cast<int>(q.int64(1));
        if (!q.is_null(2)) packing = json::parse(q.text(2));
        events_.append_in(db, id, "status", {{"status", "running"}});
        return true;
    });
    events_.notify();
    if (!started) return;
    if (cancel->load()) {
        finish(id, shutting_down_ ? "interrupted" : "cancelled", "cancelled by request");
        return;
    }

    RunContext ctx;
    ctx.run_id = id;
    ctx.threads = threads;
    ctx.packing = std::move(packing);
    ctx.store_snapshot = [this, id](const json& counts, const std::string& bytes) {
        db_.transaction([&](Database& db) {
            auto ins = db.prepare(
                "INSERT OR REPLACE INTO run_snapshots(run_id, stage, seq, grains, membrane_particles, contacts, data) "
                "VALUES (?, ?, (SELECT COUNT(*) FROM run_snapshots WHERE run_id = ?), ?, ?, ?, ?)");
            ins.bind_all(id, counts.at("stage").get<std::string>(), id, counts.at("grains").get<std::int64_t>(),
                         counts.at("membrane_particles").get<std::int64_t>(), counts.at("contacts").get<std::int64_t>(),
                         Blob{bytes});
            ins.run();
        });
    };
    ctx.cancel_requested = [cancel] { return cancel->load(); };
    ctx.emit = [this, id](const std::string& type, const json& data) {
        if (type == "progress" || type == "stage") {
            db_.transaction([&](Database& db) {
                events_.append_in(db, id, type, data);
                if (type == "progress") {
                    auto up = db.prepare("UPDATE runs SET stage = ?, progress_pct = ?, eta_s = ? WHERE id = ?");
                    up.bind_all(data.value("stage", std::string()), data.value("progress_pct", 0.0),
                                data.contains("eta_s") && data["eta_s"].is_number()
                                    ? std::optional<double>(data["eta_s"].get<double>())
                                    : std::optional<double>(),
                                id);
                    up.run();
                } else {
                    auto up = db.prepare("UPDATE runs SET stage = ? WHERE id = ?");
                    up.bind_all(data.value("stage", std::string()), id);
                    up.run();
                }
            });
            events_.notify();
        } else {
            events_.append(id, type, data);
        }
    };

    try {
        const json doc = executor_(scheme, ctx);
        db_.transaction([&](Database& db) {
            auto ins = db.prepare("INSERT INTO run_results(run_id, result_json) VALUES (?, ?)");
            ins.bind_all(id, doc.dump());
            ins.run();
            auto up = db.prepare(
                "UPDATE runs SET status = 'done', stage = 'done', progress_pct = 100, eta_s = 0, finished_at = ? "
                "WHERE id = ?");
            up.bind_all(utc_now(), id);
            up.run();
            events_.append_in(db, id, "done", {{"status", "done"}});
        });
        events_.notify();
        cancel_flags_.forget(id);
    } catch (const RunCancelled&) {
        finish(id, shutting_down_ ? "interrupted" : "cancelled",
               shutting_down_ ? "the service stopped during the run; re-run it" : "cancelled by request");
    } catch (const std::exception& e) {
        finish(id, cancel->load() && shutting_down_ ? "interrupted" : "failed", e.what());
    }
}

void RunService::begin_shutdown() {
    shutting_down_ = true;
    cancel_flags_.raise_all();
}

}  // namespace triax::service
