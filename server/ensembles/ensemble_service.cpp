#include "server/ensembles/ensemble_service.hpp"

#include "server/http/problem.hpp"
#include "server/io/ensemble_json.hpp"
#include "server/io/scheme_json.hpp"
#include "server/scaleout/ensemble.hpp"
#include "server/scaleout/task_runner.hpp"
#include "server/store/scheme_store.hpp"

namespace triax::service {

using nlohmann::json;

namespace {

const char* kSelectEnsembles =
    "SELECT id, scheme_id, name, seeds, status, members_done, members_total, concurrency, created_at, started_at, "
    "finished_at, error FROM ensembles";

json ensemble_json(Statement& st) {
    auto opt_text = [&](int c) { return st.is_null(c) ? json(nullptr) : json(st.text(c)); };
    const auto done = st.int64(5), total = st.int64(6);
    return {{"id", st.int64(0)},
            {"scheme_id", st.int64(1)},
            {"name", st.text(2)},
            {"seeds", st.text(3)},
            {"status", st.text(4)},
            {"members_done", done},
            {"members_total", total},
            {"progress_pct", total > 0 ? 100.0 * static_cast<double>(done) / static_cast<double>(total) : 0.0},
            {"concurrency", st.int64(7)},
            {"created_at", st.text(8)},
            {"started_at", opt_text(9)},
            {"finished_at", opt_text(10)},
            {"error", opt_text(11)}};
}

}  // namespace

EnsembleService::EnsembleService(Database& db, JobQueue& queue, int default_concurrency, int max_concurrency)
    : db_(db), default_concurrency_(default_concurrency), max_concurrency_(max_concurrency),
      jobs_(db, queue, JobKind{"ensemble", "ensembles", nullptr, true, "", "submit it again"}, *this) {}

json EnsembleService::submit(std::int64_t scheme_id, const std::string& seeds_text, std::size_t members,
                             std::optional<int> concurrency) {
    const int n = concurrency.value_or(default_concurrency_);
    if (n < 1 || n > max_concurrency_)
        throw unprocessable("concurrency = " + std::to_string(n) + " is outside [1, " + std::to_string(max_concurrency_) +
                            "]")
            .at_field("/concurrency")
            .with_limit("1 <= concurrency <= " + std::to_string(max_concurrency_));
    const auto id = jobs_.submit([&](Database& db) {
        const auto name = SchemeStore::name_in(db, scheme_id, "/scheme_id");
        auto ins = db.prepare(
            "INSERT INTO ensembles(scheme_id, name, seeds, status, members_total, concurrency, created_at) "
            "VALUES (?, ?, ?, 'queued', ?, ?, ?)");
        ins.bind_all(scheme_id, name, seeds_text, static_cast<std::int64_t>(members), n, utc_now());
        ins.run();
        return db.last_insert_id();
    });
    return {{"id", id}, {"status", "queued"}};
}

json EnsembleService::status(std::int64_t id) {
    return db_.with([&](Database& db) {
        auto st = db.prepare(std::string(kSelectEnsembles) + " WHERE id = ?");
        st.bind_all(id);
        if (!st.step()) throw not_found("ensemble " + std::to_string(id) + " does not exist");
        auto out = ensemble_json(st);
        auto r = db.prepare("SELECT summary_json FROM ensemble_results WHERE ensemble_id = ?");
        r.bind_all(id);
        out["summary"] = r.step() ? json::parse(r.text(0)) : json(nullptr);
        return out;
    });
}

json EnsembleService::list(const PageRequest& page) {
    return db_.with([&](Database& db) { return read_page(db, page, "ensembles", kSelectEnsembles, "id", ensemble_json, "status"); });
}

std::string EnsembleService::band_csv(std::int64_t id, const std::string& which) {
    const std::string column = which == "shear_band" ? "shear_band_csv" : which == "creep_band" ? "creep_band_csv" : "";
    if (column.empty()) throw std::logic_error("no band table '" + which + "'");
    const std::string state = status(id)["status"];
    if (state != "done") throw conflict("ensemble " + std::to_string(id) + " is " + state + "; its bands exist once done");
    return db_.with([&](Database& db) {
        // `column` is one of two fixed names, never client text.
        auto st = db.prepare("SELECT " + column + " FROM ensemble_results WHERE ensemble_id = ?");
        st.bind_all(id);
        if (!st.step()) throw not_found("ensemble " + std::to_string(id) + " has no stored result");
        return st.text(0);
    });
}

JobWork::StoreResult EnsembleService::run(std::int64_t id, const std::function<bool()>& cancelled) {
    json scheme_json;
    std::string seeds_text, name;
    int concurrency = 1;
    db_.with([&](Database& db) {
        auto q = db.prepare(
            "SELECT s.scheme_json, e.seeds, e.concurrency, e.name FROM ensembles e JOIN schemes s ON s.id = e.scheme_id "
            "WHERE e.id = ?");
        q.bind_all(id);
        q.step();
        scheme_json = json::parse(q.text(0));
        seeds_text = q.text(1);
        concurrency = static_cast<int>(q.int64(2));
        name = q.text(3);
    });
    auto scheme = io::scheme_from_json(scheme_json);
    // Members run side by side, one engine thread each: `concurrency` threads in all.
    scheme.threads = 1;
    const auto seeds = scaleout::parse_seed_list(seeds_text);
    std::vector<std::string> tasks;
    for (auto s : seeds) tasks.push_back(scaleout::member_task(s));
    const auto handler = scaleout::member_handler(scheme, cancelled);
    // A member that ran to its end (or failed) counts; one stopped by a cancel does not.
    const auto on_done = [&](std::size_t) {
        if (cancelled()) return;
        db_.transaction([&](Database& db) {
            auto up = db.prepare("UPDATE ensembles SET members_done = members_done + 1 WHERE id = ? AND status = 'running'");
            up.bind_all(id);
            up.run();
        });
    };
    const auto results = scaleout::run_tasks_in_threads(tasks, handler, concurrency, on_done);
    if (cancelled()) throw JobCancelled();
    std::vector<diagnose::EnsembleMember> members;
    for (std::size_t i = 0; i < seeds.size(); ++i) members.push_back(scaleout::member_from_result(seeds[i], results[i]));
    const auto summary = diagnose::summarise_ensemble(name, std::move(members));
    if (summary.ok == 0) {
        const auto& first = summary.members.front();
        throw std::runtime_error("no member ran to its end; seed " + std::to_string(first.seed) + ": " + first.error);
    }
    return [id, doc = io::ensemble_to_json(summary, true).dump(), shear = io::shear_band_csv(summary),
            creep = io::creep_band_csv(summary)](Database& db) {
        auto ins = db.prepare(
            "INSERT INTO ensemble_results(ensemble_id, summary_json, shear_band_csv, creep_band_csv) VALUES (?, ?, ?, ?)");
        ins.bind_all(id, doc, shear, creep);
        ins.run();
    };
}

}  // namespace triax::service
