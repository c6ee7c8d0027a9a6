#pragma once
// RunObserver: how a caller (CLI, service job, diagnosis) follows a running protocol.
// Called from the thread that runs the test; implementations must be cheap or hand off.
// The default implementation ignores everything and never cancels.
#include <string>

#include "engine/protocol/specimen_snapshot.hpp"
#include "engine/protocol/test_result.hpp"

namespace triax {
class World;
}

namespace triax::protocol {

// One physical-time piece of a creep stage (diagnostics of the increment schedule: bench
// programs log it to check that a stage's curve does not follow the schedule).
struct CreepIncrementLog {
    int stage = 0;
    double t_stage_s = 0.0;      // stage time at the piece's end
    double dt_s = 0.0;           // the piece (after splitting)
    long hold_cycles = 0;        // cycles of the relaxation that followed it
    long crushing_events = 0;    // contact return maps (yielding) during that relaxation
    double deformation_m = 0.0;  // axial deformation after the relaxation
};

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
    virtual void creep_increment(const CreepIncrementLog&) {}
    // The specimen at the end of "generation", "consolidation", "shear" and each
    // "creep-k" stage (specimen_snapshot.hpp). Copy what is kept: the reference is valid
    // only during the call.
    virtual void on_snapshot(const SpecimenSnapshot&) {}
    // The specimen's world as a stage ends ("generation", "consolidation", "shear",
    // "creep-k"): read it, do not keep the reference (the statistical contract's ensemble,
    // tests/support/reference_ensemble.hpp, reads the energy books here).
    virtual void stage_ended(const std::string& /*stage*/, const World& /*world*/) {}
    // Polled between increments; returning true ends the run with result.cancelled = true.
    virtual bool cancel_requested() { return false; }
};

}  // namespace triax::protocol
