// How rough is the DEM response the diagnosis calibrates, and how faithful is a reduced
// specimen? Drained shear of the reduced test specimen (50 x 100 mm) at the given
// confining pressure; prints q and volumetric strain at fixed axial strains for:
//   - several packings (seeds) at the nominal parameters: specimen-to-specimen scatter,
//     the floor below which no calibration can fit lab data from another specimen;
//   - one packing (common random numbers) with friction and modulus nudged by 1-2 %:
//     whether the objective is smooth at the scale of a refinement step;
//   - rolling resistance mu_r = 0.3 and grain breakage: the size of the effects the loop
//     must detect, compared with the scatter above;
//   - crush: grain crushability x = 0.6 MPa / crushing strength (the diagnosis's
//     bond_degradation parameter, 0 = unbreakable) from 0 to 2, and x = 1 on other packings:
//     how the crushing signal compares with the packing scatter at this sigma3.
// Usage: diagnose_dem_noise [r_min_mm=2.5] [sigma3_kPa=100] [max_strain_pct=5] [runs=all|seeds|sweep|effects|mimic|crush]
// Runs one case per thread on 2 threads (OMP_NUM_THREADS=1 inside each run).
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "engine/diagnose/dem_forward_model.hpp"
#include "engine/protocol/triaxial_test.hpp"
#include "tests/support/reduced_specimen.hpp"

using triax::protocol::TestScheme;

namespace {

// Wall time at which shear starts (generation + consolidation before it).
struct ShearClock final : triax::protocol::RunObserver {
    std::chrono::steady_clock::time_point shear_start = std::chrono::steady_clock::now();
    void stage_changed(const std::string& stage, int, double, double) override {
        if (stage == "shear") shear_start = std::chrono::steady_clock::now();
    }
};

struct Case {
    std::string label;
    TestScheme scheme;
};

double interp(const std::vector<double>& x, const std::vector<double>& y, double xq) {
    if (x.empty()) return 0.0;
    if (xq <= x.front()) return y.front();
    for (std::size_t j = 1; j < x.size(); ++j)
        if (xq <= x[j]) {
            const double w = (xq - x[j - 1]) / (x[j] - x[j - 1]);
            return (1 - w) * y[j - 1] + w * y[j];
        }
    return y.back();
}

}  // namespace

int main(int argc, char** argv) {
    const double r_min = (argc > 1 ? std::atof(argv[1]) : 2.5) * 1e-3;
    const double s3 = (argc > 2 ? std::atof(argv[2]) : 100.0) * 1e3;
    const double eps_max = (argc > 3 ? std::atof(argv[3]) : 5.0) * 1e-2;
    const std::string which = argc > 4 ? argv[4] : "all";

    // The specimen of the diagnosis's DEM tests (one definition for both).
    TestScheme base = triax::testing::reduced_scheme(r_min, eps_max, 11);
    base.loading.confining_pressure_pa = s3;

    std::vector<Case> cases;
    if (which == "all" || which == "seeds")
        for (std::uint64_t seed : {11, 7, 13, 17}) {
            Case c{"seed " + std::to_string(seed), base};
            c.scheme.seed = seed;
            cases.push_back(c);
        }
    if (which == "all" || which == "sweep") {
        for (double mu : {0.41, 0.42, 0.44, 0.48}) {
            Case c{"mu " + std::to_string(mu).substr(0, 4), base};
            c.scheme.micro.friction = mu;
            cases.push_back(c);
        }
        for (double f : {1.02, 1.1}) {
            Case c{"E x" + std::to_string(f).substr(0, 4), base};
            c.scheme.micro.normal_modulus_pa *= f;
            c.scheme.micro.shear_modulus_pa *= f;
            cases.push_back(c);
        }
    }
    if (which == "all" || which == "effects") {
        Case r{"mu_r 0.3", base};
        r.scheme.micro.rolling_friction = 0.3;
        cases.push_back(r);
        Case b{"breakage 3", base};
        b.scheme.effects.accelerated_bond_corrosion = true;
        b.scheme.effects.bond_corrosion_scale = 3.0;
        cases.push_back(b);
    }

    if (which == "mimic") {
        // Can the base parameters at their prior bounds (friction 0.7, bond scale 3 or 10)
        // mimic a hidden rolling resistance of 0.25 (lab seed 7 and the model's seed 11)?
        for (std::uint64_t seed : {7, 11}) {
            Case r{"mu_r .25 s" + std::to_string(seed), base};
            r.scheme.seed = seed;
            r.scheme.micro.rolling_friction = 0.25;
            cases.push_back(r);
        }
        cases.push_back({"nominal", base});
        for (double mu : {0.4, 0.7})
            for (double b : {1.0, 3.0, 10.0}) {
                if (mu == 0.4 && b == 1.0) continue;
                Case c{"mu " + std::to_string(mu).substr(0, 3) + " b x" + std::to_string(b).substr(0, 4), base};
                c.scheme.micro.friction = mu;
                c.scheme.micro.bond_normal_strength_pa *= b;
                c.scheme.micro.bond_shear_strength_pa *= b;
                cases.push_back(c);
            }
    }

    if (which == "crush") {
        // The diagnosis's mapping (dem_forward_model.cpp): sigma0 = 0.6 MPa / x.
        for (double x : {0.0, 0.25, 0.5, 0.75, 1.0, 1.5, 2.0}) {
            Case c{"crush x" + std::to_string(x).substr(0, 4), base};
            c.scheme.micro.crushing_strength_pa = x > 0.0 ? triax::diagnose::kCrushabilityReferencePa / x : 0.0;
            cases.push_back(c);
        }
        for (std::uint64_t seed : {7, 13, 17})
            for (double x : {0.0, 1.0}) {
                Case c{"s" + std::to_string(seed) + " crush x" + std::to_string(x).substr(0, 3), base};
                c.scheme.seed = seed;
                c.scheme.micro.crushing_strength_pa = x > 0.0 ? triax::diagnose::kCrushabilityReferencePa / x : 0.0;
                cases.push_back(c);
            }
    }

    const double probes[] = {0.005, 0.01, 0.02, 0.03, 0.04, 0.05, 0.08, 0.12};
    std::vector<std::string> lines(cases.size());
    std::atomic<std::size_t> next{0};
    std::mutex io;
    auto worker = [&] {
        for (std::size_t i; (i = next.fetch_add(1)) < cases.size();) {
            const auto t0 = std::chrono::steady_clock::now();
            ShearClock clock;
            const auto r = triax::protocol::run_triaxial_test(cases[i].scheme, clock, triax::protocol::Phase::Shear);
            const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            const double t_shear = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock.shear_start).count();
            std::vector<double> e, q, v;
            for (const auto& p : r.shear) e.push_back(p.axial_strain), q.push_back(p.q_pa), v.push_back(p.volumetric_strain);
            char buf[256];
            std::snprintf(buf, sizeof buf, "%-12s n=%4d %6.1fs (shear %5.1fs)  q[kPa]:", cases[i].label.c_str(),
                          r.particle_count, dt, t_shear);
            std::string line = buf;
            for (double x : probes) {
                if (x > eps_max + 1e-9) break;
                std::snprintf(buf, sizeof buf, " %6.1f", interp(e, q, x) / 1e3);
                line += buf;
            }
            line += "  ev[%]:";
            for (double x : probes) {
                if (x > eps_max + 1e-9) break;
                std::snprintf(buf, sizeof buf, " %6.3f", 100.0 * interp(e, v, x));
                line += buf;
            }
            std::snprintf(buf, sizeof buf, "  breakage %.3g J", r.energies.empty() ? 0.0 : r.energies.back().breakage_j);
            line += buf;
            std::lock_guard<std::mutex> lock(io);
            std::printf("%s\n", line.c_str());
            std::fflush(stdout);
            lines[i] = line;
        }
    };
    std::printf("r_min %.2f mm, sigma3 %.0f kPa, shear to %.1f %%; columns at axial strain (%%):", r_min * 1e3, s3 / 1e3,
                eps_max * 100);
    for (double x : probes)
        if (x <= eps_max + 1e-9) std::printf(" %.1f", x * 100);
    std::printf("\n");
    std::thread t(worker);
    worker();
    t.join();
    return 0;
}
