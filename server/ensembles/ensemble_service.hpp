#pragma once
// Ensembles as a resource, beside RunService and DiagnosisService: one scheme run at
// several seeds (packings) as ONE job of the queue. The job runs the members on threads of
// this process (scaleout::run_tasks_in_threads, as `triax ensemble` does without mpirun),
// counts them in `members_done` as they finish, and stores the summary (mean and band of
// every curve, share of seeds in each creep regime; engine/diagnose/seed_ensemble.hpp) with
// its 'done' in one transaction. State lives in `ensembles`, the result in
// `ensemble_results`; the lifecycle is the JobService's (server/jobs/job_service.hpp): a job
// left queued or running by a killed process is 'interrupted'. Ensembles have no event log.
#include "server/http/paging.hpp"
#include "server/jobs/job_queue.hpp"
#include "server/jobs/job_service.hpp"
#include "server/store/database.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <string>

namespace triax::service {

class EnsembleService : private JobWork {
public:
    // Members of one ensemble: each is a whole DEM run, and the job holds one worker.
    static constexpr std::size_t kMaxSeeds = 16;

    // default_concurrency: members run at once when the request does not say (each member
    // on one engine thread); max_concurrency: the machine's threads a job may take.
    EnsembleService(Database& db, JobQueue& queue, int default_concurrency, int max_concurrency);

    // Start-up (and after a stop): ensembles left queued or running become "interrupted".
    int recover_interrupted() { return jobs_.recover_interrupted(); }
    // Stores a queued ensemble of the stored scheme (404 naming /scheme_id if unknown) at
    // the seeds of `seeds_text` (scaleout::parse_seed_list syntax, already checked by the
    // route: 1 to kMaxSeeds seeds) and enqueues it; 422 naming /concurrency outside
    // [1, max_concurrency]; 429 when the queue is full (nothing is kept). {"id", "status"}.
    nlohmann::json submit(std::int64_t scheme_id, const std::string& seeds_text, std::size_t members,
                          std::optional<int> concurrency);
    // A queued ensemble is withdrawn; a running one stops at its members' next cancel poll.
    // 409 when it has finished, 404 when unknown.
    void cancel(std::int64_t id) { jobs_.cancel(id); }

    // {"id","scheme_id","name","seeds","status","members_done","members_total",
    //  "progress_pct","concurrency","created_at","started_at","finished_at","error"}
    // and, in status() once done, "summary" (bands in lab units). 404 if unknown.
    nlohmann::json status(std::int64_t id);
    nlohmann::json list(const PageRequest& page);  // newest first, without summaries
    // "shear_band" or "creep_band" as CSV; 404 if unknown, 409 until done.
    std::string band_csv(std::int64_t id, const std::string& which);

    // Graceful stop: running ensembles are asked to stop and recorded "interrupted".
    void begin_shutdown() { jobs_.begin_shutdown(); }

private:
    StoreResult run(std::int64_t id, const std::function<bool()>& cancelled) override;
    Database& db_;
    int default_concurrency_, max_concurrency_;
    JobService jobs_;
};

}  // namespace triax::service
