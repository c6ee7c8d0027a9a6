#pragma once
// The lifecycle every job of the service shares (runs, diagnoses, ensembles):
//
//   submit -> queued -> running -> done | failed | cancelled | interrupted
//
// A job is a row of its table (id, status, error, finished_at, and started_at when the
// kind records it) and, for kinds with an event log, its events. Every state change and its
// event are written in one transaction, so the row and the stream never disagree, even
// after kill -9. What differs between kinds is a small strategy, JobWork, called once per
// job: it reads the job's input, runs it (polling the cancel flag) and hands back the
// writer of its result.
//
// Rules of the ending (the same for every kind):
//  - a job whose cancel flag was raised ends "cancelled" ("interrupted" when the service is
//    stopping), whatever its work threw;
//  - any other exception ends it "failed" with the exception's text;
//  - a queued job that is cancelled is withdrawn from the queue and ends "cancelled";
//  - at start-up, jobs left queued or running by an earlier process end "interrupted".
#include "server/events/event_log.hpp"
#include "server/jobs/cancel_flags.hpp"
#include "server/jobs/job_queue.hpp"
#include "server/store/database.hpp"

#include <atomic>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>

namespace triax::service {

// What a job's work throws when it sees its cancel flag raised (any exception does, once
// the flag is raised; this one says so).
struct JobCancelled : std::runtime_error {
    JobCancelled() : std::runtime_error("cancelled by request") {}
};

// What a kind of job does. Called once per job on a worker, never per step of it.
class JobWork {
public:
    virtual ~JobWork() = default;
    // Writes a finished job's result inside the transaction that marks it done.
    using StoreResult = std::function<void(Database&)>;
    // Runs job `id` (just marked running); `cancelled` is its flag, to poll. Returns the
    // writer of its result; throws to fail (JobCancelled when it stops on its flag).
    virtual StoreResult run(std::int64_t id, const std::function<bool()>& cancelled) = 0;
};

struct JobKind {
    std::string noun;               // "run": queue keys ("run:7") and messages ("run 7 is ...")
    std::string table;              // "runs": a fixed identifier from the code, never user input
    EventLog* events = nullptr;     // the kind's event log; nullptr: it has none
    bool records_start = true;      // the table has started_at
    std::string on_end;             // extra assignments when it ends not done (", eta_s = NULL")
    std::string again = "re-run it";  // what the user does after an interruption
};

class JobService {
public:
    JobService(Database& db, JobQueue& queue, JobKind kind, JobWork& work);

    // Inserts a job with `insert` (inside a transaction; returns the new id, throws to
    // refuse), records its "queued" event and enqueues it. 429 (nothing kept) when the
    // queue is full, with `full_detail` when given.
    std::int64_t submit(const std::function<std::int64_t(Database&)>& insert, const std::string& full_detail = "");
    // 404 if unknown, 409 once it has ended; a queued job is withdrawn, a running one stops
    // at its next cancel poll.
    void cancel(std::int64_t id);
    // 404 if unknown, 409 unless it has ended: what a re-run checks first.
    void require_ended(std::int64_t id);
    // The job's status ("queued", ...); 404 if unknown.
    std::string state(std::int64_t id);
    // Start-up: jobs left queued or running become "interrupted". Returns how many.
    int recover_interrupted();
    // Graceful stop: running jobs are asked to stop and end "interrupted".
    void begin_shutdown();

    const JobKind& kind() const { return kind_; }

private:
    void execute(std::int64_t id, const CancelFlags::Flag& cancel);
    bool start(std::int64_t id);
    void complete(std::int64_t id, const JobWork::StoreResult& store);
    void end(std::int64_t id, const std::string& status, const std::string& detail);
    std::string key(std::int64_t id) const { return kind_.noun + ":" + std::to_string(id); }
    std::string name(std::int64_t id) const { return kind_.noun + " " + std::to_string(id); }

    Database& db_;
    JobQueue& queue_;
    JobKind kind_;
    JobWork& work_;
    CancelFlags cancel_flags_;
    std::atomic<bool> shutting_down_{false};
};

// A job's status ends it: nothing will change it any more.
bool is_ended(const std::string& status);

}  // namespace triax::service
