// Full-size paper group benchmark: generation, consolidation, shear to 15 % (or failure),
// 4 creep stages of 2.5 days each (the paper's ~10-day group), on the full 100 x 200 mm
// specimen with the preset's DEM gradation (docs/parameters.md, "Paper-group gradation").
// Reports particle counts, wall time per phase and in total, and the summary.
// Usage: paper_group [A|B|C|D|E] [threads] [out.json|-] [--shear-only] [--reduced] [--stage-hours H]
// (--reduced: the 50 x 100 mm specimen of the protocol tests, same sigma3, for comparison;
//  --stage-hours H: every creep stage lasts H hours instead of the preset's 2.5 days, the
//  short benchmark of docs/engine.md, "Performance of the full-size paper group")
// Run with OMP_WAIT_POLICY=passive on a shared machine (spinning threads steal the core).
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <string>
#include <vector>

#include <sys/resource.h>

#include "engine/protocol/paper_groups.hpp"
#include "engine/protocol/triaxial_test.hpp"
#include "server/io/result_json.hpp"

namespace {
// Wall time of each stage as the protocol announces them (a stage ends when the next starts).
class PhaseClock : public triax::protocol::RunObserver {
public:
    void stage_changed(const std::string& stage, int, double, double) override {
        const auto now = std::chrono::steady_clock::now();
        if (!phases_.empty()) phases_[current_].second += std::chrono::duration<double>(now - since_).count();
        since_ = now;
        // Generation and consolidation run twice (shear specimen, creep specimen): summed.
        for (std::size_t k = 0; k < phases_.size(); ++k)
            if (phases_[k].first == stage) { current_ = k; return; }
        phases_.push_back({stage, 0.0});
        current_ = phases_.size() - 1;
    }
    // Progress on stderr every 10 s of wall time (long runs on a loaded machine).
    void progress(const std::string& stage, double fraction, double eta_s) override {
        const auto now = std::chrono::steady_clock::now();
        if (std::chrono::duration<double>(now - last_print_).count() < 10.0) return;
        last_print_ = now;
        std::fprintf(stderr, "%s %.0f %% ETA %.0f s\n", stage.c_str(), fraction * 100, eta_s);
    }
    void print() const {
        for (const auto& p : phases_)
            if (p.first != "done") std::printf("  %-14s %7.1f s\n", p.first.c_str(), p.second);
    }

private:
    std::vector<std::pair<std::string, double>> phases_;
    std::size_t current_ = 0;
    std::chrono::steady_clock::time_point since_ = std::chrono::steady_clock::now();
    std::chrono::steady_clock::time_point last_print_ = since_;
};
}  // namespace

int main(int argc, char** argv) {
    const std::string group = argc > 1 ? argv[1] : "B";
    auto scheme = triax::protocol::paper_group(group);
    if (argc > 2) scheme.threads = std::stoi(argv[2]);
    bool shear_only = false, reduced = false;
    for (int k = 1; k < argc; ++k) {
        shear_only |= std::strcmp(argv[k], "--shear-only") == 0;
        reduced |= std::strcmp(argv[k], "--reduced") == 0;
        if (std::strcmp(argv[k], "--stage-hours") == 0 && k + 1 < argc)
            for (double& d : scheme.loading.stage_durations_s) d = 3600.0 * std::stod(argv[k + 1]);
    }
    if (reduced) {
        // The reduced specimen of tests/protocol/triaxial_protocol_test.cpp (faithfulness check).
        scheme.specimen.diameter_m = 0.05;
        scheme.specimen.height_m = 0.1;
        scheme.gradation.r_min_m = 2.5e-3;
        scheme.gradation.radius_ratio = 3.0;
        scheme.seed = 11;
    }
    PhaseClock clock;
    const auto t0 = std::chrono::steady_clock::now();
    triax::protocol::TestResult r;
    try {
        r = triax::protocol::run_triaxial_test(scheme, clock,
                                               shear_only ? triax::protocol::Phase::Shear : triax::protocol::Phase::Creep);
    } catch (const std::exception& e) {
        std::printf("group %s failed after %.1f s: %s\n", group.c_str(),
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), e.what());
        clock.print();
        return 1;
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    const double cpu = ru.ru_utime.tv_sec + 1e-6 * ru.ru_utime.tv_usec + ru.ru_stime.tv_sec + 1e-6 * ru.ru_stime.tv_usec;
    std::printf("group %s: soil particles %d, membrane particles %d, total steps %ld, wall time %.1f s (threads %d)\n",
                group.c_str(), r.particle_count, r.membrane_particle_count, r.total_steps, wall, scheme.threads);
    std::printf("CPU time (user + sys) %.1f s, %.0f %% of one core\n", cpu, 100.0 * cpu / wall);
    std::printf("wall time per phase (generation/consolidation summed over the shear and creep specimens):\n");
    clock.print();
    std::printf("initial porosity %.3f, consolidated porosity %.3f, consolidation steps %ld, ratio %.2e\n",
                r.initial_porosity, r.consolidation.porosity, r.consolidation.steps,
                r.consolidation.unbalanced_force_ratio);
    std::printf("q_f = %.1f kPa at %.2f %%, max inertial number %.2e (scaled grain density %.0f kg/m3), shear points %zu\n",
                r.q_failure_pa * 1e-3, r.axial_strain_at_failure * 100, r.max_inertial_number,
                r.inertial_density_kg_m3, r.shear.size());
    double vmax = -1.0;
    for (const auto& p : r.shear) vmax = std::max(vmax, p.volumetric_strain);
    if (!r.shear.empty())
        std::printf("volumetric strain: max contraction %.2f %%, final %.2f %% at axial %.2f %%\n", vmax * 100,
                    r.shear.back().volumetric_strain * 100, r.shear.back().axial_strain * 100);
    for (const auto& s : r.creep_stages) {
        // DEM steps of the stage: from its first to its last energy sample (phase 2 + k).
        long first = -1, last = -1;
        for (const auto& e : r.energies)
            if (e.phase_index == 1 + s.stage) { if (first < 0) first = e.step; last = e.step; }
        std::printf("stage %d S=%.2f: instant %.4f mm, final %.4f mm, elastic share %.3f, 30-min share %.0f %% "
                    "(of the whole stage deformation %.0f %%), converged %d, accelerating %d, ruptured at %.1f h, steps %ld\n",
                    s.stage, s.stress_level, s.instant_deformation_m * 1e3, s.final_deformation_m * 1e3,
                    s.elastic_share, s.share_in_first_30min * 100, s.total_share_in_first_30min * 100, s.converged,
                    s.accelerating, s.ruptured ? s.rupture_time_s / 3600.0 : -1.0, last - first);
    }
    std::printf("creep relaxations %ld\n", r.creep_relaxations);
    for (double eps : {0.01, 0.02, 0.04, 0.06, 0.08, 0.10, 0.15})
        for (const auto& p : r.shear)
            if (p.axial_strain >= eps) {
                std::printf("  eps_a %5.2f %%: q %7.1f kPa, eps_v %6.2f %%\n", p.axial_strain * 100, p.q_pa * 1e-3,
                            p.volumetric_strain * 100);
                break;
            }
    if (argc > 3 && argv[3][0] != '-')
        std::ofstream(argv[3]) << triax::io::result_to_json(r).dump();
    return 0;
}
