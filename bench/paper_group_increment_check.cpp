// Time-increment convergence of the creep scheduler: runs the reduced group-B creep test
// twice, the second with every physical-time increment halved (first increment / 2,
// growth sqrt(growth), cap / 2), and reports the largest difference between the two
// translated creep curves relative to each stage's creep. Stated tolerance: 10 % of the
// stage's creep deformation (docs/creep.md). Usage: paper_group_increment_check [threads]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

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
    TestScheme s;
    s.specimen.diameter_m = 0.05;
    s.specimen.height_m = 0.1;
    s.gradation.r_min_m = 2.5e-3;
    s.gradation.radius_ratio = 3.0;
    s.loading.stage_durations_s = {86400.0, 86400.0, 86400.0, 86400.0};
    if (argc > 1) s.threads = std::stoi(argv[1]);
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
        ok = ok && worst <= 0.1 * creep;
    }
    std::printf("%s (tolerance 10 %%)\n", ok ? "within tolerance" : "OUTSIDE tolerance");
    return ok ? 0 : 1;
}
