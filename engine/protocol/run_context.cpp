#include "engine/protocol/run_context.hpp"

#include <algorithm>

namespace triax::protocol {

Progress::Progress(RunObserver& o, int creep_stages) : obs_(o), start_(std::chrono::steady_clock::now()) {
    const double creep_w = creep_stages > 0 ? 0.55 / creep_stages : 0.0;
    weights_ = {0.1, 0.1, 0.25};
    for (int k = 0; k < creep_stages; ++k) weights_.push_back(creep_w);
}

void Progress::report(const std::string& stage, int phase, double fraction) {
    double done = 0.0;
    for (int k = 0; k < phase && k < static_cast<int>(weights_.size()); ++k) done += weights_[k];
    done += weights_[std::min<int>(phase, weights_.size() - 1)] * std::clamp(fraction, 0.0, 1.0);
    double total = 0.0;
    for (double w : weights_) total += w;
    const double f = done / total;
    const double el = elapsed();
    obs_.progress(stage, f, f > 0.02 ? el * (1.0 - f) / f : -1.0);
    if (obs_.cancel_requested()) throw Cancelled{};
}

double Progress::elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

EnergySample energy_sample(const World& w, int phase, double time_s) {
    const auto& e = w.energy();
    EnergySample s;
    s.phase_index = phase;
    s.step = w.step();
    s.time_s = time_s;
    s.strain_j = e.strain;
    s.slip_j = e.slip;
    s.damping_j = e.damping;
    s.kinetic_j = e.kinetic;
    s.bond_j = e.bond_strain;
    s.boundary_work_j = e.boundary_work;
    s.creep_j = e.creep;
    s.breakage_j = e.breakage;
    return s;
}

}  // namespace triax::protocol
