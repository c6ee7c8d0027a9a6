#include "engine/protocol/creep_hold.hpp"

#include <cmath>

namespace triax::protocol {

CreepHold::CreepHold(Specimen& sp, double sigma3, const PlatenServo& servo, double ubf_tolerance)
    : sp_(sp), sigma3_(sigma3), servo_(servo), ubf_tol_(ubf_tolerance) {}

void CreepHold::add_rotation(std::vector<Vec3>* rotation, long cycles) {
    if (!rotation) return;
    World& w = sp_.world();
    const auto& omega = w.particles().angular_velocity;
    for (int i = 0; i < sp_.soil_count(); ++i) (*rotation)[i] += omega[i] * (cycles * w.time_step());
}

long CreepHold::hold(double sigma1_target, long min_cycles, long max_cycles, std::vector<Vec3>* rotation) {
    constexpr long kChunk = PlatenServo::kChunk;
    World& w = sp_.world();
    const double dt = w.time_step();
    auto& top = w.plane_wall(sp_.top_wall());
    long n = 0;
    bool done = false;
    for (; n < max_cycles; n += kChunk) {
        const double area = sp_.volume() / sp_.height();
        top.velocity = Vec3(0, 0, -servo_.velocity(sigma1_target, top.normal_stress(area), area, dt));
        sp_.cycle(kChunk, sigma3_);
        add_rotation(rotation, kChunk);
        if (n < min_cycles) continue;  // n: cycles before this chunk
        if (std::abs(sigma1_target - sp_.top_stress()) >= kStressTolerance * sigma1_target) continue;
        if (w.unbalanced_force_ratio() >= kUbfFactor * ubf_tol_) continue;
        n += kChunk;
        done = true;
        break;
    }
    top.velocity.setZero();
    ++stats_.holds;
    stats_.cycles += n;
    if (!done) ++stats_.at_max;
    return n;
}

}  // namespace triax::protocol
