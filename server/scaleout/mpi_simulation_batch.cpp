#include "server/scaleout/mpi_simulation_batch.hpp"

#include <exception>

#include "server/scaleout/wire_format.hpp"

namespace triax::scaleout {

using namespace triax::diagnose;

std::string simulate_request(const ForwardModel& model, std::string_view request) {
    SimulationOutcome out;
    try {
        const SimulationRequest r = decode_request(request);
        out.curves = model.simulate(r.point, r.seed);
        out.ok = true;
    } catch (const std::exception& e) {
        out.ok = false;
        out.error = e.what();
    }
    return encode_outcome(out);
}

std::vector<SimulationOutcome> MpiSimulationBatch::run(const ForwardModel& model,
                                                       const std::vector<SimulationRequest>& requests,
                                                       const std::function<void(std::size_t)>& on_done) {
    std::vector<std::string> tasks;
    tasks.reserve(requests.size());
    for (const auto& r : requests) tasks.push_back(encode_request(r));
    const TaskHandler local = [&model](std::string_view t) { return simulate_request(model, t); };
    const auto results = pool_.run(tasks, local, on_done);
    std::vector<SimulationOutcome> out(results.size());
    for (std::size_t i = 0; i < results.size(); ++i) {
        if (!results[i].ok) {
            out[i].error = results[i].bytes;
            continue;
        }
        try {
            out[i] = decode_outcome(results[i].bytes);
        } catch (const std::exception& e) {
            out[i].ok = false;
            out[i].error = e.what();
        }
    }
    return out;
}

void MpiSimulationBatch::serve(MpiTaskPool& pool, const ForwardModel& model) {
    pool.serve([&model](std::string_view t) { return simulate_request(model, t); });
}

}  // namespace triax::scaleout
