// Full-size paper group benchmark: generation, consolidation, shear to 15 %, 4 creep
// stages of 2.5 days each (the paper's ~10-day group), on the full 100 x 200 mm specimen
// with the paper's gradation (Rmin 0.5 mm, Rmax/Rmin 39.712). Reports wall time, particle
// counts and the summary. Usage: paper_group [A|B|C|D|E] [threads] [out.json]
#include <chrono>
#include <exception>
#include <cstdio>
#include <fstream>
#include <string>

#include "engine/protocol/paper_groups.hpp"
#include "engine/protocol/triaxial_test.hpp"
#include "server/io/result_json.hpp"

int main(int argc, char** argv) {
    const std::string group = argc > 1 ? argv[1] : "B";
    auto scheme = triax::protocol::paper_group(group);
    if (argc > 2) scheme.threads = std::stoi(argv[2]);
    triax::protocol::RunObserver quiet;
    const auto t0 = std::chrono::steady_clock::now();
    triax::protocol::TestResult r;
    try {
        r = triax::protocol::run_triaxial_test(scheme, quiet);
    } catch (const std::exception& e) {
        std::printf("group %s failed after %.1f s: %s\n", group.c_str(),
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), e.what());
        return 1;
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("group %s: soil particles %d, membrane particles %d, total steps %ld, wall time %.1f s (threads %d)\n",
                group.c_str(), r.particle_count, r.membrane_particle_count, r.total_steps, wall, scheme.threads);
    std::printf("q_f = %.1f kPa at %.2f %%, consolidation ratio %.2e, max inertial number %.2e\n", r.q_failure_pa * 1e-3,
                r.axial_strain_at_failure * 100, r.consolidation.unbalanced_force_ratio, r.max_inertial_number);
    for (const auto& s : r.creep_stages)
        std::printf("stage %d S=%.2f: instant %.3f mm, final %.3f mm, 30-min share %.0f %%, converged %d, accelerating %d\n",
                    s.stage, s.stress_level, s.instant_deformation_m * 1e3, s.final_deformation_m * 1e3,
                    s.share_in_first_30min * 100, s.converged, s.accelerating);
    if (argc > 3) std::ofstream(argv[3]) << triax::io::result_to_json(r).dump();
    return 0;
}
