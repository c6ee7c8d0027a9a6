#include "server/jobs/job_service.hpp"

#include "server/http/problem.hpp"

#include <vector>

namespace triax::service {

bool is_ended(const std::string& status) {
    return status == "done" || status == "failed" || status == "cancelled" || status == "interrupted";
}

JobService::JobService(Database& db, JobQueue& queue, JobKind kind, JobWork& work)
    : db_(db), queue_(queue), kind_(std::move(kind)), work_(work) {}

std::int64_t JobService::submit(const std::function<std::int64_t(Database&)>& insert, const std::string& full_detail) {
    const auto id = db_.transaction([&](Database& db) {
        const auto new_id = insert(db);
        if (kind_.events) kind_.events->append_in(db, new_id, "status", {{"status", "queued"}});
        return new_id;
    });
    const auto flag = cancel_flags_.arm(id);
    if (!queue_.try_submit(key(id), [this, id, flag] { execute(id, flag); })) {
        // Nothing of a refused job is kept: the client was told 429 and will retry.
        db_.transaction([&](Database& db) {
            if (kind_.events) kind_.events->forget_in(db, id);
            auto del = db.prepare("DELETE FROM " + kind_.table + " WHERE id = ?");
            del.bind_all(id);
            del.run();
        });
        cancel_flags_.forget(id);
        throw full_detail.empty() ? queue_full(queue_) : queue_full(queue_, full_detail);
    }
    return id;
}

std::string JobService::state(std::int64_t id) {
    return db_.with([&](Database& db) {
        auto st = db.prepare("SELECT status FROM " + kind_.table + " WHERE id = ?");
        st.bind_all(id);
        if (!st.step()) throw not_found(name(id) + " does not exist");
        return st.text(0);
    });
}

void JobService::cancel(std::int64_t id) {
    const auto s = state(id);
    if (is_ended(s)) throw conflict(name(id) + " is already " + s);
    cancel_flags_.raise(id);
    if (queue_.withdraw(key(id))) end(id, "cancelled", "cancelled by request before it started");
}

void JobService::require_ended(std::int64_t id) {
    const auto s = state(id);
    if (!is_ended(s))
        throw conflict(name(id) + " is " + s + "; only a finished " + kind_.noun + " can be re-run");
}

int JobService::recover_interrupted() {
    std::vector<std::int64_t> ids;
    db_.with([&](Database& db) {
        auto st = db.prepare("SELECT id FROM " + kind_.table + " WHERE status IN ('queued', 'running') ORDER BY id");
        while (st.step()) ids.push_back(st.int64(0));
    });
    for (auto id : ids) end(id, "interrupted", "the service stopped before the " + kind_.noun + " ended; " + kind_.again);
    return static_cast<int>(ids.size());
}

void JobService::begin_shutdown() {
    shutting_down_ = true;
    cancel_flags_.raise_all();
}

bool JobService::start(std::int64_t id) {
    const bool started = db_.transaction([&](Database& db) {
        auto up = db.prepare("UPDATE " + kind_.table + " SET status = 'running'" +
                             (kind_.records_start ? ", started_at = ?" : "") + " WHERE id = ? AND status = 'queued'");
        if (kind_.records_start) up.bind_all(utc_now(), id);
        else up.bind_all(id);
        up.run();
        if (db.changes() == 0) return false;
        if (kind_.events) kind_.events->append_in(db, id, "status", {{"status", "running"}});
        return true;
    });
    if (kind_.events) kind_.events->notify();
    return started;
}

void JobService::complete(std::int64_t id, const JobWork::StoreResult& store) {
    db_.transaction([&](Database& db) {
        auto up = db.prepare("UPDATE " + kind_.table +
                             " SET status = 'done', error = NULL, finished_at = ? WHERE id = ? AND status = 'running'");
        up.bind_all(utc_now(), id);
        up.run();
        if (db.changes() == 0) return;  // ended by someone else (a stop)
        if (store) store(db);
        if (kind_.events) kind_.events->append_in(db, id, "done", {{"status", "done"}});
    });
    if (kind_.events) kind_.events->notify();
    cancel_flags_.forget(id);
}

void JobService::end(std::int64_t id, const std::string& status, const std::string& detail) {
    db_.transaction([&](Database& db) {
        auto up = db.prepare("UPDATE " + kind_.table + " SET status = ?, error = ?, finished_at = ?" + kind_.on_end +
                             " WHERE id = ? AND status IN ('queued', 'running')");
        up.bind_all(status, detail, utc_now(), id);
        up.run();
        if (db.changes() == 0) return;  // already ended by someone else
        if (kind_.events) kind_.events->append_in(db, id, "error", {{"status", status}, {"detail", detail}});
    });
    if (kind_.events) kind_.events->notify();
    cancel_flags_.forget(id);
}

void JobService::execute(std::int64_t id, const CancelFlags::Flag& cancel) {
    if (!start(id)) return;
    const auto stopped = [&] {
        if (shutting_down_) end(id, "interrupted", "the service stopped during the " + kind_.noun + "; " + kind_.again);
        else end(id, "cancelled", "cancelled by request");
    };
    if (cancel->load()) return stopped();
    try {
        complete(id, work_.run(id, [&cancel] { return cancel->load(); }));
    } catch (const std::exception& e) {
        if (cancel->load()) return stopped();
        end(id, "failed", e.what());
    }
}

}  // namespace triax::service
