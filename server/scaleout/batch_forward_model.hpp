#pragma once
// A ForwardModel whose simulate() goes through a SimulationBatch (one request per call):
// how the diagnosis loop, which calls simulate() from `concurrency` threads, reaches MPI
// ranks through run_diagnosis(lab, model, ...). Parameters and effects are the inner
// model's; a failed run throws its message, as the inner model would have.
#include <stdexcept>

#include "engine/diagnose/simulation_batch.hpp"

namespace triax::scaleout {

class BatchForwardModel final : public diagnose::ForwardModel {
public:
    BatchForwardModel(const diagnose::ForwardModel& inner, diagnose::SimulationBatch& batch)
        : inner_(inner), batch_(batch) {}

    std::vector<diagnose::ParameterSpec> base_parameters() const override { return inner_.base_parameters(); }
    std::vector<diagnose::ParameterSpec> effect_parameters(diagnose::Effect e) const override {
        return inner_.effect_parameters(e);
    }
    bool includes(diagnose::Effect e) const override { return inner_.includes(e); }
    diagnose::LabDataset simulate(const diagnose::ModelPoint& point, std::uint64_t seed) const override {
        auto out = batch_.run(inner_, {{point, seed}}, {});
        if (!out.at(0).ok) throw std::runtime_error(out[0].error);
        return std::move(out[0].curves);
    }

private:
    const diagnose::ForwardModel& inner_;
    diagnose::SimulationBatch& batch_;
};

}  // namespace triax::scaleout
