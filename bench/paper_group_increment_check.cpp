// Time-increment convergence of the creep scheduler: runs the reduced group-B creep test
// twice, the second with every physical-time increment halved (first increment / 2,
// growth sqrt(growth), cap / 2), and reports the largest difference between the two
// translated creep curves relative to each stage's creep. Stated tolerance: 10 % of the
// stage's creep deformation (docs/creep.md).
// Usage: paper_group_increment_check [threads] [key=value ...]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "bench/reduced_creep_args.hpp"
#include "engine/protocol/triaxial_test.hpp"

using namespace triax::protocol;

namespace {
double at(const CreepStageResult& s, double t) {
    const auto& c = s.translated;
    for (std::size_t k = 1; k < c.size(); ++k)
        if (c[k].time_s >= t) {
            const double w = (t - c[k - 1].time_s) / (c[k].time_s - c[k - 1].time_s);
            return c[k - 1].axial_deformation_m + w * (c[k].axial_deformation_m - c[k - 1].axial_deformation_m);
        }
    return c.back().axial_deformation_m;
}
}  // namespace

int main(int argc, char** argv) {
    // The reduced creep specimen of the tests with the scheme's default increments and
    // 1-day stages; a leading bare number is the thread count, then key=value overrides
    // (bench/reduced_creep_args.hpp, e.g. crush=1 t0=...).
    auto args = triax::bench::reduced_creep_defaults();
    const TestScheme plain;
    args.scheme.creep.first_increment_s = plain.creep.first_increment_s;
    args.scheme.creep.increment_growth = plain.creep.increment_growth;
    args.scheme.creep.max_increment_s = plain.creep.max_increment_s;
    args.scheme.loading.max_axial_strain = plain.loading.max_axial_strain;
    args.hours = 24.0;
    int first = 1;
    if (argc > 1 && std::string(argv[1]).find('=') == std::string::npos) {
        args.scheme.threads = std::stoi(argv[1]);
        first = 2;
    }
    if (!triax::bench::parse_creep_args(args, argc, argv, first)) return 2;
    const TestScheme s = args.scheme;
    TestScheme h = s;
    h.creep.first_increment_s /= 2.0;
    h.creep.increment_growth = std::sqrt(h.creep.increment_growth);
    h.creep.max_increment_s /= 2.0;
    const auto a = run_triaxial_test(s), b = run_triaxial_test(h);
    bool ok = true;
    for (std::size_t k = 0; k < std::min(a.creep_stages.size(), b.creep_stages.size()); ++k) {
        const auto &sa = a.creep_stages[k], &sb = b.creep_stages[k];
        const double creep = std::max(1e-9, std::abs(sa.final_deformation_m - sa.instant_deformation_m));
        double worst = 0.0;
        for (const auto& p : sa.translated)
            worst = std::max(worst, std::abs((p.axial_deformation_m - sa.instant_deformation_m) -
                                             (at(sb, p.time_s) - sb.instant_deformation_m)));
        std::printf("stage %zu: max |difference| of creep curves %.4f mm = %.1f %% of the stage's creep (%.4f mm)\n",
                    k + 1, worst * 1e3, 100.0 * worst / creep, creep * 1e3);
        // The regime verdicts must not hang on the schedule either (the collapse rule reads
        // one increment's creep against the loading step).
        auto verdict = [](const CreepStageResult& st) {
            char buf[96];
            std::snprintf(buf, sizeof buf, "accelerating %d converged %d ruptured %d at %.1f h", st.accelerating, st.converged,
                          st.ruptured, st.ruptured ? st.rupture_time_s / 3600.0 : -1.0);
            return std::string(buf);
        };
        std::printf("  increments as scheduled: %s\n  increments halved:       %s\n", verdict(sa).c_str(), verdict(sb).c_str());
        ok = ok && worst <= 0.1 * creep;
    }
    if (a.creep_stages.size() != b.creep_stages.size())
        std::printf("stage count differs: %zu as scheduled, %zu halved (a rupture ends the test)\n", a.creep_stages.size(),
                    b.creep_stages.size());
    std::printf("%s (tolerance 10 %%)\n", ok ? "within tolerance" : "OUTSIDE tolerance");
    return ok ? 0 : 1;
}
