#include "server/runs/run_service.hpp"

#include "server/http/problem.hpp"
#include "server/store/scheme_store.hpp"

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

}  // namespace

RunService::RunService(Database& db, EventLog& events, JobQueue& queue, RunExecutor executor, int default_threads,
                       int max_threads)
    : db_(db), events_(events), queue_(queue), executor_(std::move(executor)), default_threads_(default_threads),
      max_threads_(max_threads), jobs_(db, queue, JobKind{"run", "runs", &events, true, ", eta_s = NULL", "re-run it"}, *this) {}

json RunService::submit(std::int64_t scheme_id, std::optional<int> threads, std::optional<std::int64_t> rerun_of,
                        std::optional<std::int64_t> packing_id) {
    const int n_threads = threads.value_or(default_threads_);
    if (n_threads < 1 || n_threads > max_threads_)
        throw unprocessable("threads = " + std::to_string(n_threads) + " is outside [1, " + std::to_string(max_threads_) +
                            "]")
            .at_field("/threads")
            .with_limit("1 <= threads <= " + std::to_string(max_threads_));
    const auto id = jobs_.submit(
        [&](Database& db) {
            const auto name = SchemeStore::name_in(db, scheme_id, "/scheme_id");
            if (packing_id) {
                auto pk = db.prepare("SELECT 1 FROM packings WHERE id = ?");
                pk.bind_all(*packing_id);
                if (!pk.step())
                    throw not_found("packing " + std::to_string(*packing_id) + " does not exist").at_field("/packing_id");
            }
            auto ins = db.prepare(
                "INSERT INTO runs(scheme_id, name, status, threads, rerun_of, created_at, packing_id) VALUES (?, ?, "
                "'queued', ?, ?, ?, ?)");
            ins.bind_all(scheme_id, name, n_threads, rerun_of, utc_now(), packing_id);
            ins.run();
            return db.last_insert_id();
        },
        "the run queue is full (" + std::to_string(queue_.limit()) + " waiting runs); retry later");
    return {{"id", id}, {"status", "queued"}};
}

json RunService::rerun(std::int64_t id) {
    jobs_.require_ended(id);
    const auto st = status(id);
    const auto packing_id = db_.with([&](Database& db) {
        auto q = db.prepare("SELECT packing_id FROM runs WHERE id = ?");
        q.bind_all(id);
        q.step();
        return q.is_null(0) ? std::optional<std::int64_t>() : std::optional<std::int64_t>(q.int64(0));
    });
    return submit(st["scheme_id"].get<std::int64_t>(), st["threads"].get<int>(), id, packing_id);
}

json RunService::status(std::int64_t id) {
    return db_.row(std::string(kStatusColumns) + " WHERE r.id = ?", id,
                   NotFound::row("run", id), status_row);
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

void RunService::emit(std::int64_t id, const std::string& type, const json& data) {
    if (type != "progress" && type != "stage") {
        events_.append(id, type, data);
        return;
    }
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
}

JobWork::StoreResult RunService::run(std::int64_t id, const std::function<bool()>& cancelled) {
    RunContext ctx;
    ctx.run_id = id;
    json scheme;
    db_.with([&](Database& db) {
        auto q = db.prepare(
            "SELECT s.scheme_json, r.threads, p.packing_json FROM runs r JOIN schemes s ON s.id = r.scheme_id "
            "LEFT JOIN packings p ON p.id = r.packing_id WHERE r.id = ?");
        q.bind_all(id);
        q.step();
        scheme = json::parse(q.text(0));
        ctx.threads = static_cast<int>(q.int64(1));
        if (!q.is_null(2)) ctx.packing = json::parse(q.text(2));
    });
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
    ctx.cancel_requested = cancelled;
    ctx.emit = [this, id](const std::string& type, const json& data) { emit(id, type, data); };

    const std::string doc = executor_(scheme, ctx).dump();
    return [id, doc](Database& db) {
        auto ins = db.prepare("INSERT INTO run_results(run_id, result_json) VALUES (?, ?)");
        ins.bind_all(id, doc);
        ins.run();
        auto up = db.prepare("UPDATE runs SET stage = 'done', progress_pct = 100, eta_s = 0 WHERE id = ?");
        up.bind_all(id);
        up.run();
    };
}

}  // namespace triax::service
