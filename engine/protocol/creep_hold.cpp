#include "engine/protocol/creep_hold.hpp"

#include <algorithm>
#include <cmath>
#include <deque>

#include "engine/protocol/servo_gain.hpp"

namespace triax::protocol {

CreepHold::CreepHold(Specimen& sp, double sigma3, double k_skeleton, double v_max, double v_quasi_static,
                     double ubf_tolerance, const HoldOptions& options)
    : sp_(sp), sigma3_(sigma3), k_skel_(k_skeleton), v_max_(v_max), v_qs_(v_quasi_static), ubf_tol_(ubf_tolerance),
      opt_(options) {}

void CreepHold::add_rotation(std::vector<Vec3>* rotation, long cycles) {
    if (!rotation) return;
    World& w = sp_.world();
    const auto& omega = w.particles().angular_velocity;
    for (int i = 0; i < sp_.soil_count(); ++i) (*rotation)[i] += omega[i] * (cycles * w.time_step());
}

long CreepHold::ramp(double sigma1_target, long max_cycles, std::vector<Vec3>* rotation) {
    auto& top = sp_.world().plane_wall(sp_.top_wall());
    const double s0 = sp_.top_stress();
    const double sign = sigma1_target > s0 ? 1.0 : -1.0;  // loading or unloading
    long n = 0;
    // The platen accelerates to the shear speed over kRampAcceleration cycles: started at
    // full speed, the grains at the platen are hit before the skeleton behind them moves
    // (measured: +100 kPa in the first 10 cycles on the reduced specimen, which ended the
    // ramp at once). Checked every 10 cycles: the stress passes the target by at most one
    // such step.
    while (n < max_cycles && sign * (sigma1_target - sp_.top_stress()) > 0.0) {
        const double ramp_up = std::min(1.0, static_cast<double>(n + kRampChunk) / kRampAcceleration);
        top.velocity = Vec3(0, 0, -sign * v_qs_ * ramp_up);
        sp_.cycle(kRampChunk, sigma3_);
        add_rotation(rotation, kRampChunk);
        n += kRampChunk;
    }
    top.velocity.setZero();
    return n;
}

long CreepHold::hold(double sigma1_target, long min_cycles, long max_cycles, std::vector<Vec3>* rotation,
                     bool loading) {
    const long ramp_cycles = loading && opt_.loading_ramp ? ramp(sigma1_target, max_cycles, rotation) : 0;
    const bool adaptive = opt_.adaptive_gain && (opt_.adaptive_loading || !loading);
    // A faster servo must not make the hold a dynamic load: its platen is capped at the
    // quasi-static shear test's speed.
    const double v_cap = adaptive && opt_.quasi_static_speed ? std::min(v_max_, v_qs_) : v_max_;
    World& w = sp_.world();
    const double dt = w.time_step();
    AdaptiveServoGain gain;
    auto& top = w.plane_wall(sp_.top_wall());
    // Platen positions at the ends of the last chunks (criterion (R)), oldest first.
    std::deque<double> z_hist{sp_.top_z()};
    const int window = std::max(1, opt_.rest_window_chunks);
    long n = 0;
    bool done = false;
    double last_error = 0.0, last_boost = 0.0;  // the previous chunk's (for the tangent stiffness)
    for (; n < max_cycles - ramp_cycles; n += kChunk) {
        const double area = sp_.volume() / sp_.height();
        const double measured = top.normal_stress(area);
        const double error = sigma1_target - measured;
        double boost = 1.0;
        if (adaptive) {
            boost = gain.update(error);
            // The share of the error the last chunk closed, per unit boost: the specimen's
            // tangent stiffness relative to the assumed one (x 0.2). The boost may not close
            // more than a third of the error per chunk: the load approaches its target
            // from one side, as the base gain's does (an overshoot is a load the stage
            // never asked for, and its extra deformation would be read as instant).
            if (opt_.no_overshoot && last_boost > 0.0 && last_error != 0.0)
                boost = gain.cap((last_error - error) / last_error / last_boost);
            last_error = error;
            last_boost = boost;
        }
        // PFC-style servo: platen speed proportional to the stress error, the base gain
        // closing 20 % of the error per chunk on the assumed skeleton stiffness.
        const double g = 0.2 * boost * area / (k_skel_ * dt * kChunk);
        top.velocity = Vec3(0, 0, -std::clamp(g * error, -v_cap, v_cap));
        sp_.cycle(kChunk, sigma3_);
        add_rotation(rotation, kChunk);
        if (opt_.rest_criterion) {
            z_hist.push_back(sp_.top_z());
            if (static_cast<int>(z_hist.size()) > window + 1) z_hist.pop_front();
        }
        if (n < min_cycles) continue;  // n: cycles before this chunk (as before the split)
        const double tol = opt_.stress_tolerance;
        const double error_end = sigma1_target - sp_.top_stress();
        if (std::abs(error_end) >= tol * sigma1_target) continue;
        if (w.unbalanced_force_ratio() >= opt_.ubf_factor * ubf_tol_) continue;
        if (opt_.drift_criterion && adaptive && !hold_servo_settled(gain.boost(), error_end, tol, sigma1_target))
            continue;
        if (opt_.rest_criterion &&
            (static_cast<int>(z_hist.size()) < window + 1 ||
             !hold_at_rest(z_hist.back(), z_hist.front(), sp_.height(), opt_.rest_strain_per_kcycle, window * kChunk)))
            continue;
        n += kChunk;
        done = true;
        break;
    }
    top.velocity.setZero();
    n += ramp_cycles;
    ++stats_.holds;
    stats_.cycles += n;
    if (!done) ++stats_.at_max;
    if (opt_.log) opt_.log->push_back({sigma1_target, n, !done, ramp_cycles});
    return n;
}

}  // namespace triax::protocol
