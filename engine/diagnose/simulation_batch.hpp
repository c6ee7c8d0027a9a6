#pragma once
// How a diagnosis (or an ensemble) gets its forward runs done: it hands a batch of
// independent requests to a SimulationBatch and reads back one outcome per request.
// Implementations: ThreadSimulationBatch (threads in this process, below) and the MPI batch
// of the `triax` CLI (server/scaleout/), which spreads the same requests over ranks.
//
// Contract: outcome i depends only on request i (the model point and its seed), never on
// how many workers there are or in which order they finish, so a diagnosis gives the same
// report for the same seed whatever the number of threads or ranks.
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "engine/diagnose/forward_model.hpp"

namespace triax::diagnose {

struct SimulationRequest {
    ModelPoint point;
    std::uint64_t seed = 1;
};

struct SimulationOutcome {
    bool ok = false;
    LabDataset curves;   // the model's curves when ok
    std::string error;   // the engine's message when not ok (e.g. "particle escaped the domain box")
};

class SimulationBatch {
public:
    virtual ~SimulationBatch() = default;
    // Runs every request of the batch; outcomes[i] belongs to requests[i]. `on_done` (may be
    // empty) is called once per finished request, from any thread, for progress. A request
    // whose run throws gives ok = false with the message; cancellation is the model's own
    // (DemForwardModel polls its observer inside each run).
    virtual std::vector<SimulationOutcome> run(const ForwardModel& model, const std::vector<SimulationRequest>& requests,
                                               const std::function<void(std::size_t)>& on_done) = 0;
    // Requests that can run at once (threads or ranks): the calibration sizes its batches by it.
    virtual int width() const = 0;
};

// Requests spread over `concurrency` threads of this process.
class ThreadSimulationBatch final : public SimulationBatch {
public:
    explicit ThreadSimulationBatch(int concurrency) : concurrency_(concurrency < 1 ? 1 : concurrency) {}

    std::vector<SimulationOutcome> run(const ForwardModel& model, const std::vector<SimulationRequest>& requests,
                                       const std::function<void(std::size_t)>& on_done) override {
        std::vector<SimulationOutcome> out(requests.size());
        std::atomic<std::size_t> next{0};
        auto worker = [&] {
            for (std::size_t i; (i = next.fetch_add(1)) < requests.size();) {
                try {
                    out[i].curves = model.simulate(requests[i].point, requests[i].seed);
                    out[i].ok = true;
                } catch (const std::exception& e) {
                    out[i].ok = false;
                    out[i].error = e.what();
                }
                if (on_done) on_done(i);
            }
        };
        const std::size_t threads = std::min<std::size_t>(static_cast<std::size_t>(concurrency_), requests.size());
        std::vector<std::thread> pool;
        for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(worker);
        worker();
        for (auto& t : pool) t.join();
        return out;
    }
    int width() const override { return concurrency_; }

private:
    int concurrency_;
};

}  // namespace triax::diagnose
