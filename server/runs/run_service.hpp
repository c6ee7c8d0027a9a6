#pragma once
// Runs as a resource: creation (queued), the job that executes one run on a worker, cancel,
// re-run, status, and recovery at start-up. A run's state lives in the `runs` table and its
// history in `run_events`; the lifecycle is the JobService's (server/jobs/job_service.hpp),
// this class is what is particular to a run: its row, its executor and its result.
#include "server/events/event_log.hpp"
#include "server/http/paging.hpp"
#include "server/jobs/job_queue.hpp"
#include "server/jobs/job_service.hpp"
#include "server/runs/result_cache.hpp"
#include "server/runs/run_executor.hpp"
#include "server/store/database.hpp"

#include <optional>

namespace triax::service {

class RunService : private JobWork {
public:
    RunService(Database& db, EventLog& events, JobQueue& queue, RunExecutor executor, int default_threads,
               int max_threads);

    // Start-up: runs left queued or running by a previous process become "interrupted"
    // (with an error event, so their streams end). Returns how many.
    int recover_interrupted() { return jobs_.recover_interrupted(); }

    // Inserts a queued run and enqueues it. ApiError 429 when the queue is full, 422 for a
    // thread count outside [1, max_threads].
    // packing_id: the stored packing the run starts from (404 if unknown); a re-run keeps it.
    nlohmann::json submit(std::int64_t scheme_id, std::optional<int> threads, std::optional<std::int64_t> rerun_of = {},
                          std::optional<std::int64_t> packing_id = {});
    void cancel(std::int64_t id) { jobs_.cancel(id); }
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
    void begin_shutdown() { jobs_.begin_shutdown(); }

private:
    StoreResult run(std::int64_t id, const std::function<bool()>& cancelled) override;
    void emit(std::int64_t id, const std::string& type, const nlohmann::json& data);
    Database& db_;
    EventLog& events_;
    JobQueue& queue_;
    RunExecutor executor_;
    int default_threads_, max_threads_;
    ResultCache results_{16};
    JobService jobs_;
};

}  // namespace triax::service
