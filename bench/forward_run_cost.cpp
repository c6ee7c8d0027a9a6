// What one forward run of the diagnosis costs, and how much its curve scatters between
// packings. Drained shear of a cohesionless specimen (no bonds, no crushing) to a given
// strain without the softening stop, at several seeds: prints per seed the particle counts,
// DEM steps per phase, particle-steps and wall time, q and ev at fixed strains; then the
// mean and the packing scatter (coefficient of variation of q) per strain. Each lever of the
// calibration specimen (size, membrane sphere size, consolidation tolerance, inertial number)
// is one key; run it with and without the lever on the same seeds.
// Usage: forward_run_cost [key=value ...]
//   sigma3_kPa=100 strain_pct=15 seeds=1,2,3 d_mm=50 h_mm=100 r_min_mm=2.5 ratio=3 mu=0.3
//   tol=1e-3 membrane_r_mm=0 inertial=5e-4 porosity=0.35 boundary=membrane|grain_pressure
// Runs one seed per thread on 2 threads (one OpenMP thread inside each run).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "engine/protocol/triaxial_test.hpp"
#include "bench/key_value_args.hpp"

namespace {

double interp(const std::vector<double>& x, const std::vector<double>& y, double xq) {
    if (x.empty()) return NAN;
    if (xq <= x.front()) return y.front();
    for (std::size_t j = 1; j < x.size(); ++j)
        if (xq <= x[j]) {
            const double w = (xq - x[j - 1]) / (x[j] - x[j - 1]);
            return (1 - w) * y[j - 1] + w * y[j];
        }
    return NAN;  // not reached
}

}  // namespace

int main(int argc, char** argv) {
    std::map<std::string, std::string> kv{{"sigma3_kPa", "100"}, {"strain_pct", "15"}, {"seeds", "1,2,3"},
                                          {"d_mm", "50"},        {"h_mm", "100"},      {"r_min_mm", "2.5"},
                                          {"ratio", "3"},        {"mu", "0.3"},        {"tol", "1e-3"},
                                          {"membrane_r_mm", "0"}, {"inertial", "5e-4"}, {"porosity", "0.35"},
                                          {"boundary", "membrane"}};
    if (!triax::bench::read_key_values(argc, argv, kv)) return 2;
    auto num = [&](const char* k) { return std::atof(kv[k].c_str()); };
    triax::protocol::TestScheme base;
    base.name = "forward-run-cost";
    base.specimen.diameter_m = num("d_mm") * 1e-3;
    base.specimen.height_m = num("h_mm") * 1e-3;
    base.specimen.target_porosity = num("porosity");
    base.gradation.r_min_m = num("r_min_mm") * 1e-3;
    base.gradation.radius_ratio = num("ratio");
    base.micro.friction = num("mu");
    base.micro.bond_normal_strength_pa = 0.0;
    base.micro.bond_shear_strength_pa = 0.0;
    base.micro.membrane_particle_radius_m = num("membrane_r_mm") * 1e-3;
    if (kv["boundary"] == "grain_pressure")
        base.specimen.lateral_boundary = triax::protocol::SpecimenSpec::LateralBoundary::GrainPressure;
    else if (kv["boundary"] != "membrane") {
        std::fprintf(stderr, "boundary: '%s' is not membrane or grain_pressure\n", kv["boundary"].c_str());
        return 2;
    }
    base.effects.moisture_bonding = false;
    base.loading.confining_pressure_pa = num("sigma3_kPa") * 1e3;
    base.loading.max_axial_strain = num("strain_pct") * 1e-2;
    base.loading.consolidation_tolerance = num("tol");
    base.loading.max_inertial_number = num("inertial");
    base.loading.stop_at_softening = false;
    std::vector<std::uint64_t> seeds;
    {
        std::stringstream ss(kv["seeds"]);
        for (std::string t; std::getline(ss, t, ',');) seeds.push_back(std::strtoull(t.c_str(), nullptr, 10));
    }
    const double probes[] = {0.005, 0.01, 0.02, 0.05, 0.10, 0.15};
    struct Row {
        std::vector<double> q, ev;
        double wall = 0, psteps = 0;
    };
    std::vector<Row> rows(seeds.size());
    std::atomic<std::size_t> next{0};
    std::mutex io;
    auto worker = [&] {
        for (std::size_t i; (i = next.fetch_add(1)) < seeds.size();) {
            auto s = base;
            s.seed = seeds[i];
            const auto t0 = std::chrono::steady_clock::now();
            triax::protocol::RunObserver quiet;
            triax::protocol::TestResult r;
            try {
                r = triax::protocol::run_triaxial_test(s, quiet, triax::protocol::Phase::Shear);
            } catch (const std::exception& e) {
                std::lock_guard<std::mutex> lock(io);
                std::printf("seed %3llu failed: %s\n", static_cast<unsigned long long>(seeds[i]), e.what());
                continue;
            }
            const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            std::vector<double> e, q, v;
            for (const auto& p : r.shear) e.push_back(p.axial_strain), q.push_back(p.q_pa), v.push_back(p.volumetric_strain);
            const long n_part = r.particle_count + r.membrane_particle_count;
            const long shear_steps = r.total_steps - r.consolidation.steps;
            rows[i].wall = wall;
            rows[i].psteps = static_cast<double>(n_part) * static_cast<double>(r.total_steps);
            std::string line;
            char buf[256];
            std::snprintf(buf, sizeof buf,
                          "seed %3llu grains %4d membrane %4d  steps cons %7ld (ratio %.1e) shear %7ld  %.2e particle-steps %6.1f s  q[kPa]:",
                          static_cast<unsigned long long>(seeds[i]), r.particle_count, r.membrane_particle_count,
                          r.consolidation.steps, r.consolidation.unbalanced_force_ratio, shear_steps, rows[i].psteps, wall);
            line = buf;
            for (double x : probes) {
                const double qq = interp(e, q, x);
                rows[i].q.push_back(qq);
                rows[i].ev.push_back(interp(e, v, x));
                std::snprintf(buf, sizeof buf, " %6.1f", qq / 1e3);
                line += buf;
            }
            line += "  ev[%]:";
            for (double ev : rows[i].ev) {
                std::snprintf(buf, sizeof buf, " %5.2f", 100 * ev);
                line += buf;
            }
            std::lock_guard<std::mutex> lock(io);
            std::printf("%s\n", line.c_str());
            std::fflush(stdout);
        }
    };
    std::printf("boundary %s, sigma3 %s kPa, %s x %s mm, r_min %s mm x%s, mu %s, tol %s, membrane r %s mm, I %s; q at axial strain (%%):",
                kv["boundary"].c_str(),
                kv["sigma3_kPa"].c_str(), kv["d_mm"].c_str(), kv["h_mm"].c_str(), kv["r_min_mm"].c_str(),
                kv["ratio"].c_str(), kv["mu"].c_str(), kv["tol"].c_str(), kv["membrane_r_mm"].c_str(),
                kv["inertial"].c_str());
    for (double x : probes) std::printf(" %.1f", 100 * x);
    std::printf("\n");
    std::thread t(worker);
    worker();
    t.join();
    // Packing scatter: coefficient of variation of q over the seeds at each strain.
    std::printf("mean q [kPa]:");
    std::vector<double> cv;
    for (std::size_t k = 0; k < std::size(probes); ++k) {
        double s = 0, s2 = 0;
        int n = 0;
        for (const auto& r : rows)
            if (k < r.q.size() && std::isfinite(r.q[k])) s += r.q[k], s2 += r.q[k] * r.q[k], ++n;
        const double m = n ? s / n : NAN;
        const double sd = n > 1 ? std::sqrt(std::max(0.0, (s2 - n * m * m) / (n - 1))) : NAN;
        std::printf(" %6.1f", m / 1e3);
        cv.push_back(sd / m);
    }
    std::printf("\nscatter (CV of q) [%%]:");
    for (double c : cv) std::printf(" %6.1f", 100 * c);
    std::printf("\nscatter (SD of ev) [%% strain]:");
    for (std::size_t k = 0; k < std::size(probes); ++k) {
        double s = 0, s2 = 0;
        int n = 0;
        for (const auto& r : rows)
            if (k < r.ev.size() && std::isfinite(r.ev[k])) s += r.ev[k], s2 += r.ev[k] * r.ev[k], ++n;
        const double m = n ? s / n : NAN;
        std::printf(" %6.2f", n > 1 ? 100 * std::sqrt(std::max(0.0, (s2 - n * m * m) / (n - 1))) : NAN);
    }
    std::vector<double> walls, ps;
    for (const auto& r : rows)
        if (r.wall > 0) walls.push_back(r.wall), ps.push_back(r.psteps);
    std::sort(walls.begin(), walls.end());
    std::sort(ps.begin(), ps.end());
    if (!walls.empty())
        std::printf("\nmedian wall %.1f s, median %.2e particle-steps per run\n", walls[walls.size() / 2], ps[ps.size() / 2]);
    return 0;
}
