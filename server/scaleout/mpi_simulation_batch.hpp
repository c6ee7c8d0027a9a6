#pragma once
// The forward runs of a diagnosis spread over MPI ranks: each request {ModelPoint, seed}
// travels to a rank as bytes (wire_format.hpp), the rank runs its own ForwardModel (built
// from the same scheme and dataset files as every other rank's) and sends the curves back.
// Outcome i depends only on request i, so the report is the same for any number of ranks
// (and the same as ThreadSimulationBatch's).
//
//   rank 0:        MpiSimulationBatch batch(pool); ... batch.run(model, requests, on_done)
//   ranks 1..N-1:  MpiSimulationBatch::serve(pool, model);   // until rank 0's shutdown
#include "engine/diagnose/simulation_batch.hpp"
#include "server/scaleout/mpi_task_pool.hpp"

namespace triax::scaleout {

class MpiSimulationBatch final : public diagnose::SimulationBatch {
public:
    explicit MpiSimulationBatch(MpiTaskPool& pool) : pool_(pool) {}

    // `model` runs the requests rank 0 takes itself. A run that throws (on any rank) is an
    // outcome with ok = false and the message.
    std::vector<diagnose::SimulationOutcome> run(const diagnose::ForwardModel& model,
                                                 const std::vector<diagnose::SimulationRequest>& requests,
                                                 const std::function<void(std::size_t)>& on_done) override;
    int width() const override { return pool_.width(); }

    static void serve(MpiTaskPool& pool, const diagnose::ForwardModel& model);

private:
    MpiTaskPool& pool_;
};

// One request run by `model`, answered in wire format (what a rank sends back).
std::string simulate_request(const diagnose::ForwardModel& model, std::string_view request);

}  // namespace triax::scaleout
