#pragma once
// RunObserver: how a caller (CLI, service job, diagnosis) follows a running protocol.
// Called from the thread that runs the test; implementations must be cheap or hand off.
// The default implementation ignores everything and never cancels.
#include <string>

#include "engine/protocol/test_result.hpp"

namespace triax::protocol {

// Stage names: "generation", "consolidation", "shear", "creep-1".."creep-N", "done".
class RunObserver {
public:
    virtual ~RunObserver() = default;
    // fraction in [0, 1] of the whole run; eta_s < 0 when unknown.
    virtual void progress(const std::string& /*stage*/, double /*fraction*/, double /*eta_s*/) {}
    // index: 0 before creep, k for creep stage k; stress_level and q_target only for creep.
    virtual void stage_changed(const std::string& /*stage*/, int /*index*/, double /*stress_level*/,
                               double /*q_target_pa*/) {}
    virtual void shear_point(const ShearPoint&) {}
    virtual void creep_point(int /*stage*/, const CreepPoint&) {}
    virtual void energy_sample(const EnergySample&) {}
    virtual void measurement_sample(const MeasurementSample&) {}
    // Polled between increments; returning true ends the run with result.cancelled = true.
    virtual bool cancel_requested() { return false; }
};

}  // namespace triax::protocol
