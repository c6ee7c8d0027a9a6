#pragma once
// The creep stages' stress holds: the top platen servo-controlled to sigma1 (membrane at
// sigma3) until the specimen is at rest at the held stress. Every creep reading (the
// stage's instant deformation and each increment's deformation) is taken when a hold ends,
// so the holds are the reading convention (docs/creep.md, "How DEM cycles map to physical
// time"). The convention must not depend on the servo: a reading is the deformation at
// mechanical rest, however fast the platen got there.
//
// Loading step (the instant reading), when HoldOptions::loading_ramp is on:
//   (a) the platen is driven strain-controlled at the shear test's quasi-static speed
//       (creep law frozen, as in every hold) until the platen stress reaches the target:
//       the loading path is that of the shear test, the same for every servo gain;
//   (b) then the hold below.
// Hold (the loading step's (b) and every increment's relaxation): the servo (base gain, or
// the adaptive gain of servo_gain.hpp, capped at the shear test's platen speed and by the
// measured tangent stiffness: no overshoot) until, after a chunk,
//   (1) the platen stress is within `stress_tolerance` of the target,
//   (2) the unbalanced-force ratio is below `ubf_factor` x the consolidation tolerance,
//   (R) the platen has stopped: its displacement over the last `rest_window_chunks`
//       chunks is below `rest_strain_per_kcycle` x height per 1000 cycles.
// (R) is a bound on the specimen's deformation rate in DEM cycles that comes from no
// servo gain: a P-servo that follows a still-yielding specimen moves at the yield rate
// whatever its gain, so (1) alone ends a stiff servo's hold in mid-yield and the rest of
// the yield is read in the next increment (measured: S = 0.8 "crept" 2 mm in its first
// 5 min on the full-size specimen). Why 1e-6 per 1000 cycles: docs/creep.md.
//
// HoldOptions::at_rest() selects this convention. The default HoldOptions{} are the holds
// before session 6 (no ramp, no (R); the loading hold at the base gain ended by (1) and (2),
// the increments by (1), (2) and, with the adaptive gain, criterion (3) below), bitwise.
#include <vector>

#include "engine/core/types.hpp"
#include "engine/protocol/specimen.hpp"

namespace triax::protocol {

// One hold as it ended (benchmarks' diagnosis of where the cycles go).
struct HoldRecord {
    double target_pa = 0.0;
    long cycles = 0;
    bool at_max = false;
    long ramp_cycles = 0;  // of `cycles`, the loading step's strain-controlled ramp
};

struct HoldOptions {
    // The defaults are the holds before session 6 (the protocol's default convention: base
    // gain, loading hold ended by (1) and (2)); the convention at rest is at_rest() below,
    // not the default because on the reduced CI specimen it reads too little creep at
    // S = 0.4 for test (3) (docs/creep.md, "Instant reading").
    bool adaptive_gain = false;        // AdaptiveServoGain on the base gain (servo_gain.hpp)
    bool adaptive_loading = false;     // the adaptive gain also in the loading step's hold
    bool loading_ramp = false;         // loading step (a): strain-controlled ramp at the shear speed
    bool rest_criterion = false;       // (R): the platen has stopped
    double rest_strain_per_kcycle = 1.0e-6;  // (R)'s bound: platen strain per 1000 cycles
    int rest_window_chunks = 4;        // (R) over the last 4 chunks (200 cycles)
    bool drift_criterion = true;       // legacy (3): boost |error| < tol sigma1 (adaptive increments only)
    bool no_overshoot = true;          // boost capped by the measured tangent stiffness
    bool quasi_static_speed = true;    // adaptive platen speed capped at the shear test's (I <= 5e-4)
    double stress_tolerance = 0.002;   // relative to the target sigma1
    double ubf_factor = 2.0;           // x the scheme's consolidation tolerance
    std::vector<HoldRecord>* log = nullptr;  // when given, every hold is appended

    // The convention at rest: loading ramp, then every hold (loading and increments) ended
    // by (1), (2) and (R), with the given gain in all of them.
    static HoldOptions at_rest(bool adaptive) {
        HoldOptions o;
        o.adaptive_gain = adaptive;
        o.adaptive_loading = true;
        o.loading_ramp = true;
        o.rest_criterion = true;
        o.drift_criterion = false;
        return o;
    }
};

struct HoldStats {
    long holds = 0;
    long cycles = 0;
    long at_max = 0;  // holds that ran to their maximum without meeting the criteria
};

class CreepHold {
public:
    // k_skeleton: the base gain's assumed skeleton stiffness (N/m); v_max: platen speed cap;
    // v_quasi_static: the shear test's platen speed (the loading ramp's speed and the cap
    // of the adaptive gain's platen).
    CreepHold(Specimen& sp, double sigma3, double k_skeleton, double v_max, double v_quasi_static,
              double ubf_tolerance, const HoldOptions& options);

    // Holds sigma1_target for at least min_cycles, at most max_cycles; returns the cycles
    // run. Grain rotations over the cycles are added to `rotation` (rad, soil grains) when
    // given (measurement spheres' rotation rate in physical time).
    // loading: the stage's loading step (the instant reading), else an increment's hold.
    long hold(double sigma1_target, long min_cycles, long max_cycles, std::vector<Vec3>* rotation, bool loading);

    const HoldStats& stats() const { return stats_; }
    static constexpr long kChunk = 50;      // cycles between servo updates and checks
    static constexpr long kRampChunk = 10;  // ramp: cycles between stress checks (small overshoot)
    static constexpr long kRampAcceleration = 1000;  // ramp: cycles to reach the shear speed

private:
    // Loading step (a): platen at the shear speed towards the target until the stress
    // reaches it; returns the cycles run.
    long ramp(double sigma1_target, long max_cycles, std::vector<Vec3>* rotation);
    void add_rotation(std::vector<Vec3>* rotation, long cycles);

    Specimen& sp_;
    double sigma3_, k_skel_, v_max_, v_qs_, ubf_tol_;
    HoldOptions opt_;
    HoldStats stats_;
};

// Legacy criterion (3): the platen speed the servo commands for the stress error `error`
// (Pa) at gain `boost` x base, against the base servo's speed at the band's edge.
inline bool hold_servo_settled(double boost, double error, double tol, double target_pa) {
    return boost * (error < 0 ? -error : error) < tol * target_pa;
}

// Criterion (R): the platen moved less than `strain_per_kcycle` x height per 1000 cycles
// over a window of `window_cycles` (z_then: platen position at the window's start).
inline bool hold_at_rest(double z_now, double z_then, double height, double strain_per_kcycle, long window_cycles) {
    const double d = z_now - z_then;
    return (d < 0 ? -d : d) < strain_per_kcycle * height * (1e-3 * static_cast<double>(window_cycles));
}

}  // namespace triax::protocol
