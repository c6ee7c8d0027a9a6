#pragma once
// Runs as a resource: creation (queued), the job that executes one run on a worker, cancel,
// re-run, status, and recovery at start-up. A run's state lives in the `runs` table and its
// history in `run_events`; every state change and its event are written in one transaction
// so the row and the stream never disagree, even after kill -9.
#include "server/events/event_log.hpp"
#include "server/http/paging.hpp"
#include "server/jobs/cancel_flags.hpp"
#include "server/jobs/job_queue.hpp"
#include "server/runs/result_cache.hpp"
#include "server/runs/run_executor.hpp"
#include "server/store/database.hpp"

#include <atomic>
#include <memory>
#include <optional>

namespace triax::service {

class RunService {
public:
    RunService(Database& db, EventLog& events, JobQueue& queue, RunExecutor executor, int default_threads,
               int max_threads);

    // Start-up: runs left queued or running by a previous process become "interrupted"
    // (with an error event, so their streams end). Returns how many.
    int recover_interrupted();

    // Inserts a queued run and enqueues it. ApiError 429 when the queue is full, 422 for a
    // thread count outside [1, max_threads].
    // packing_id: the stored packing the run starts from (404 if unknown); a re-run keeps it.
    nlohmann::json submit(std::int64_t scheme_id, std::optional<int> threads, std::optional<std::int64_t> rerun_of = {},
                          std::optional<std::int64_t> packing_id = {});
    void cancel(std::int64_t id);
    nlohmann::json rerun(std::int64_t id);

    nlohmann::json status(std::int64_t id);  // 404 if unknown
    nlohmann::json list(const PageRequest& page);  // newest first, one page
    bool exists(std::int64_t id);
    // The stored result document (summary + series) once done (nullptr before); parsed once
    // and kept for the last few runs (result_cache.hpp).
    ResultCache::Document result(std::int64_t id);
    // Data of every event of `type`, in order (partial series while running).
    std::vector<nlohmann::json> event_data(std::int64_t id, const std::string& type);
    // The stored snapshots of a run, in stage order: [{"stage","grains","membrane_particles","contacts"}].
    nlohmann::json snapshots(std::int64_t id);
    // One snapshot's stored form (io::decode_snapshot), if recorded.
    std::optional<std::string> snapshot_bytes(std::int64_t id, const std::string& stage);

    // Graceful stop: running runs are asked to stop and recorded as "interrupted".
    void begin_shutdown();

private:
    void execute(std::int64_t id, std::shared_ptr<std::atomic<bool>> cancel);
    void finish(std::int64_t id, const std::string& status, const std::string& detail);
    Database& db_;
    EventLog& events_;
    JobQueue& queue_;
    RunExecutor executor_;
    int default_threads_, max_threads_;
    CancelFlags cancel_flags_;
    ResultCache results_{16};
    std::atomic<bool> shutting_down_{false};
};

}  // namespace triax::service
