#pragma once
// The creep stages' stress holds: the top platen servo-controlled to sigma1 (membrane at
// sigma3) until the specimen is at rest at the held stress. Every creep reading (the
// stage's instant deformation and each increment's deformation) is taken when a hold ends,
// so the holds are the reading convention (docs/creep.md, "How DEM cycles map to physical
// time").
//
// A hold runs the platen servo (platen_servo.hpp) for at least min_cycles and ends, after
// a chunk, when
//   (1) the platen stress is within kStressTolerance (0.2 %) of the target (a looser 1 %
//       hold reads as creep at low stress levels), and
//   (2) the unbalanced-force ratio is below kUbfFactor x the consolidation tolerance,
// or at max_cycles.
#include <vector>

#include "engine/core/types.hpp"
#include "engine/protocol/platen_servo.hpp"
#include "engine/protocol/specimen.hpp"

namespace triax::protocol {

struct HoldStats {
    long holds = 0;
    long cycles = 0;
    long at_max = 0;  // holds that ran to their maximum without meeting the criteria
};

class CreepHold {
public:
    static constexpr double kStressTolerance = 0.002;  // (1), relative to the target sigma1
    static constexpr double kUbfFactor = 2.0;          // (2), x the consolidation tolerance

    CreepHold(Specimen& sp, double sigma3, const PlatenServo& servo, double ubf_tolerance);

    // Holds sigma1_target for at least min_cycles, at most max_cycles; returns the cycles
    // run. Grain rotations over the cycles are added to `rotation` (rad, soil grains) when
    // given (measurement spheres' rotation rate in physical time).
    long hold(double sigma1_target, long min_cycles, long max_cycles, std::vector<Vec3>* rotation);

    const HoldStats& stats() const { return stats_; }

private:
    void add_rotation(std::vector<Vec3>* rotation, long cycles);

    Specimen& sp_;
    double sigma3_;
    PlatenServo servo_;
    double ubf_tol_;
    HoldStats stats_;
};

}  // namespace triax::protocol
