#pragma once
// Diagnoses as a resource: creation (queued), the job that runs diagnose::run_diagnosis on
// a worker, cancel, re-run, status, listing and recovery at start-up. State lives in
// `diagnoses`, history in `diagnosis_events`; the lifecycle is the JobService's
// (server/jobs/job_service.hpp), this class is what is particular to a diagnosis.
#include "engine/diagnose/lab_data.hpp"
#include "server/events/event_log.hpp"
#include "server/http/paging.hpp"
#include "server/jobs/job_queue.hpp"
#include "server/jobs/job_service.hpp"
#include "server/store/database.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <optional>

namespace triax::diagnose {
class DiagnoseObserver;
}

namespace triax::service {

class DiagnosisService : private JobWork {
public:
    // load_dataset: the stored dataset by id (throws 404 ApiError when unknown).
    DiagnosisService(Database& db, EventLog& events, JobQueue& queue,
                     std::function<diagnose::LabDataset(std::int64_t)> load_dataset);

    // Start-up (and after a stop): diagnoses left queued or running become "interrupted".
    int recover_interrupted() { return jobs_.recover_interrupted(); }
    // Stores a queued diagnosis of `request` ({"scheme", "options"}, already validated) and
    // enqueues it; 429 when the queue is full. Returns {"id", "status"}.
    nlohmann::json submit(std::int64_t dataset_id, const nlohmann::json& request,
                          std::optional<std::int64_t> rerun_of = {});
    void cancel(std::int64_t id) { jobs_.cancel(id); }
    // A finished (done, failed, cancelled or interrupted) diagnosis started again with the
    // same dataset, scheme and options; 409 while it is queued or running.
    nlohmann::json rerun(std::int64_t id);
    nlohmann::json status(std::int64_t id);  // 404 if unknown
    nlohmann::json list(const PageRequest& page);
    bool exists(std::int64_t id);
    // Graceful stop: running diagnoses are asked to stop and recorded "interrupted".
    void begin_shutdown() { jobs_.begin_shutdown(); }
    // Where a diagnosis runs instead of in this process (the MPI launcher with --mpi-ranks):
    // (id, request, lab, observer) -> report JSON. Unset: in process.
    using RemoteRunner = std::function<nlohmann::json(std::int64_t, const nlohmann::json&, const diagnose::LabDataset&,
                                                      diagnose::DiagnoseObserver&)>;
    void set_remote_runner(RemoteRunner r) { remote_ = std::move(r); }

private:
    StoreResult run(std::int64_t id, const std::function<bool()>& cancelled) override;
    RemoteRunner remote_;
    Database& db_;
    EventLog& events_;
    std::function<diagnose::LabDataset(std::int64_t)> load_dataset_;
    JobService jobs_;
};

}  // namespace triax::service
