#include "engine/protocol/consolidation.hpp"

#include <algorithm>
#include <cmath>

#include "engine/protocol/platen_servo.hpp"

namespace triax::protocol {

namespace {
constexpr double kStressTolerance = 0.01;  // relative to sigma3
constexpr long kMinCycles = 2000;
constexpr long kMaxCycles = 400000;
}  // namespace

void consolidate_isotropically(Specimen& sp, RunContext& run) {
    constexpr long kChunk = PlatenServo::kChunk;
    const double sigma3 = run.scheme.loading.confining_pressure_pa;
    World& w = sp.world();
    // Consolidated at the compaction friction (the specimen's density), sheared at its own.
    sp.install_compaction_laws();
    sp.release_lateral_boundary();
    const double dt = w.time_step();
    const PlatenServo servo = PlatenServo::for_specimen(sp);
    run.observer.stage_changed("consolidation", 0, 0.0, 0.0);
    w.energy().reset_accumulated();
    const long start = w.step();
    double ratio = 1.0;
    for (long n = 0; n < kMaxCycles; n += kChunk) {
        const double area = sp.volume() / sp.height();
        auto& top = w.plane_wall(sp.top_wall());
        auto& bot = w.plane_wall(sp.bottom_wall());
        top.velocity = Vec3(0, 0, -servo.velocity(sigma3, top.normal_stress(area), area, dt));
        bot.velocity = Vec3(0, 0, servo.velocity(sigma3, bot.normal_stress(area), area, dt));
        sp.cycle(kChunk, sigma3);
        ratio = w.unbalanced_force_ratio();
        const bool stress_ok = std::abs(sp.axial_stress() - sigma3) < kStressTolerance * sigma3;
        if (n > kMinCycles && stress_ok && ratio < run.scheme.loading.consolidation_tolerance) break;
        if (n % 2000 == 0) run.progress.report("consolidation", 0, std::min(1.0, 0.5 * n / 20000.0));
    }
    w.plane_wall(sp.top_wall()).velocity.setZero();
    w.plane_wall(sp.bottom_wall()).velocity.setZero();
    sp.install_test_laws();
    auto& c = run.result.consolidation;
    c.unbalanced_force_ratio = ratio;
    c.porosity = sp.porosity();
    c.steps = w.step() - start;
    c.achieved_sigma3_pa = sp.axial_stress();
    run.observer.energy_sample(energy_sample(w, 0, 0.0));
    run.result.energies.push_back(energy_sample(w, 0, 0.0));
}

}  // namespace triax::protocol
