// How weak the diagnosis's base specimen can be made: the reduced membrane specimen (D 50 mm,
// 2.5-7.5 mm grains, about 200 grains, cohesionless) sheared at sigma3 to 15 % axial strain,
// over grain friction mu, platen friction and the membrane lattice's spring stiffness, on
// several seeds. Prints the porosity after consolidation, the peak friction angle
// phi_p = asin(q / (q + 2 sigma3)), the strain at the peak, q at 15 % over q_peak, and the
// largest contraction. A run that loses a grain prints its error and the sweep goes on.
// Usage: base_reach [sigma3_kpa=100] [seeds=1,2] [mu=0.05,0.3] [wall_mu=0.4] [grains=200]
//        [strain=0.15] [membrane_k=2e4] [boundary=membrane,grain_pressure] [porosity=0.35]
//        [compaction=1]
// compaction: the grains' friction during consolidation as a multiple of mu (0 = frictionless,
// dense; 1 = mu; above 1 looser); the shear runs at mu.
// porosity: the generation's target porosity (grains grown frictionless to that solid volume,
// then consolidated with friction: a looser target gives a looser specimen).
// boundary: the bonded membrane (its lattice springs at membrane_k) or the pressure on the
// outermost grains (no membrane; membrane_k does not apply, the sweep runs it once).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "engine/protocol/triaxial_test.hpp"
#include "bench/key_value_args.hpp"

using namespace triax::protocol;

namespace {
std::vector<double> list(const std::string& s) {
    std::vector<double> v;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ',')) v.push_back(std::atof(item.c_str()));
    return v;
}
}  // namespace

int main(int argc, char** argv) {
    std::map<std::string, std::string> kv{{"sigma3_kpa", "100"}, {"seeds", "1,2"}, {"mu", "0.05,0.3"},                                           {"wall_mu", "0.4"}, {"grains", "200"}, {"strain", "0.15"}, {"membrane_k", "2e4"}, {"boundary", "membrane"}, {"porosity", "0.35"},
                                          {"compaction", "1"}};
    if (!triax::bench::read_key_values(argc, argv, kv)) return 2;
    const double s3 = 1e3 * std::atof(kv["sigma3_kpa"].c_str());
    std::vector<std::string> boundaries;
    {
        std::stringstream ss(kv["boundary"]);
        std::string b;
        while (std::getline(ss, b, ',')) {
            if (b != "membrane" && b != "grain_pressure") {
                std::fprintf(stderr, "boundary: '%s' is not membrane or grain_pressure\n", b.c_str());
                return 2;
            }
            boundaries.push_back(b);
        }
    }
    std::printf("%-14s %8s %6s %6s %6s %5s %5s %9s %7s %9s %11s %11s %8s %7s %10s %9s\n", "boundary", "memb_k", "mu", "wallmu", "n0", "c_mu", "seed", "porosity", "phi_p",
                "eps_p_%", "q15/q_peak", "max_contr_%", "steps", "wall_s", "cons_steps", "cons_ubf");
    std::fflush(stdout);
    for (const std::string& boundary : boundaries)
    for (double mk : boundary == "membrane" ? list(kv["membrane_k"]) : std::vector<double>{0.0})
        for (double wall_mu : list(kv["wall_mu"]))
            for (double mu : list(kv["mu"]))
              for (double n0 : list(kv["porosity"]))
               for (double cf : list(kv["compaction"]))
                for (double seed : list(kv["seeds"])) {
                    TestScheme s;
                    s.specimen.diameter_m = 0.05;
                    s.specimen.height_m = 0.1;
                    s.gradation.r_min_m = 2.5e-3;
                    s.gradation.radius_ratio = 3.0;
                    s.max_particles = std::atoi(kv["grains"].c_str());
                    s.specimen.target_porosity = n0;
                    s.specimen.compaction_friction_ratio = cf;
                    s.micro.friction = mu;
                    s.micro.wall_friction = wall_mu;
                    if (boundary == "membrane") s.micro.membrane_stiffness_n_m = mk;
                    else s.specimen.lateral_boundary = SpecimenSpec::LateralBoundary::GrainPressure;
                    s.micro.bond_normal_strength_pa = s.micro.bond_shear_strength_pa = 0.0;
                    s.loading.confining_pressure_pa = s3;
                    s.loading.max_axial_strain = std::atof(kv["strain"].c_str());
                    s.loading.stop_at_softening = false;
                    s.seed = static_cast<unsigned>(seed);
                    s.threads = 1;
                    RunObserver quiet;
                    TestResult r;
                    const auto t0 = std::chrono::steady_clock::now();
                    try {
                        r = run_triaxial_test(s, quiet, Phase::Shear);
                    } catch (const std::exception& e) {
                        std::printf("%-14s %8.0f %6.2f %6.2f %6.3f %5.2f %5.0f  failed: %s\n", boundary.c_str(), mk, mu, wall_mu, n0, cf, seed, e.what());
                        std::fflush(stdout);
                        continue;
                    }
                    double q_peak = 0, e_peak = 0, contr = 0;
                    for (const auto& p : r.shear) {
                        if (p.q_pa > q_peak) q_peak = p.q_pa, e_peak = p.axial_strain;
                        contr = std::max(contr, p.volumetric_strain);
                    }
                    const double q_end = r.shear.empty() ? 0.0 : r.shear.back().q_pa;
                    const double phi = std::asin(q_peak / (q_peak + 2.0 * s3)) * 180.0 / 3.14159265358979;
                    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                    std::printf("%-14s %8.0f %6.2f %6.2f %6.3f %5.2f %5.0f %9.4f %7.1f %9.2f %11.2f %11.2f %8ld %7.0f %10ld %9.1e\n", boundary.c_str(), mk, mu, wall_mu, n0, cf, seed,
                                r.consolidation.porosity, phi, 100 * e_peak, q_peak > 0 ? q_end / q_peak : 0.0, 100 * contr,
                                r.total_steps, wall_s, r.consolidation.steps, r.consolidation.unbalanced_force_ratio);
                    std::fflush(stdout);
                }
    return 0;
}
