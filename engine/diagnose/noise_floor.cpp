// Packing scatter and lab reading noise (see noise_floor.hpp).
#include "engine/diagnose/noise_floor.hpp"

#include <algorithm>
#include <cmath>

#include "engine/diagnose/curve_statistics.hpp"
#include "engine/diagnose/residuals.hpp"

namespace triax::diagnose {

namespace {

bool is_creep(const ResidualSeries& s) {
    return s.quantity == Quantity::CreepStrain || s.quantity == Quantity::CreepDeformation;
}

// Sum of squared white-noise estimates of one series and their count.
std::pair<double, std::size_t> series_noise(const ResidualSeries& s) {
    // One reading per stage: its neighbours are other stages, not a curve.
    if (s.quantity == Quantity::CreepInstant) return {0.0, 0};
    double ss = 0.0;
    std::size_t n = 0;
    auto x_of = [&](std::size_t i) { return is_creep(s) ? std::log(std::max(s.x[i], 1e-3)) : s.x[i]; };
    for (std::size_t i = 1; i + 1 < s.x.size(); ++i) {
        const double x0 = x_of(i - 1), x1 = x_of(i), x2 = x_of(i + 1);
        if (!(x2 > x0) || x1 < x0 || x1 > x2) continue;
        const double w = (x2 - x1) / (x2 - x0);
        const double d = s.lab[i] - (w * s.lab[i - 1] + (1.0 - w) * s.lab[i + 1]);
        ss += d * d / (1.0 + w * w + (1.0 - w) * (1.0 - w)) / (s.scale * s.scale);
        ++n;
    }
    return {ss, n};
}

}  // namespace

std::string curve_kind(const std::string& label) {
    return label.rfind("creep", 0) == 0 || label.rfind("instant", 0) == 0 ? "creep" : "shear";
}

double lab_reading_noise(const std::vector<ResidualSeries>& layout) {
    double ss = 0.0;
    std::size_t n = 0;
    for (const auto& s : layout) {
        const auto [a, b] = series_noise(s);
        ss += a;
        n += b;
    }
    return n ? std::sqrt(ss / static_cast<double>(n)) : 0.0;
}

NoiseFloor noise_floor(const std::vector<ResidualSeries>& layout, const std::vector<std::vector<double>>& replicates) {
    NoiseFloor f;
    f.lab_nrmse = lab_reading_noise(layout);
    std::vector<const std::vector<double>*> runs;
    std::size_t n = 0;
    for (const auto& s : layout) n += s.x.size();
    for (const auto& r : replicates)
        if (r.size() == n) runs.push_back(&r);
    f.seeds = static_cast<int>(runs.size());
    if (runs.size() >= 2) {
        double ss = 0.0;
        std::size_t m = 0, at = 0;
        std::vector<std::pair<std::string, std::pair<double, std::size_t>>> by_kind;  // kind, (ss, m)
        std::vector<double> values(runs.size());
        for (const auto& s : layout) {
            double ss_c = 0.0;
            std::size_t m_c = 0;
            for (std::size_t i = 0; i < s.x.size(); ++i, ++at) {
                // 1.0 exactly is the penalty of a reading a run did not reach.
                for (std::size_t k = 0; k < runs.size(); ++k) values[k] = (*runs[k])[at];
                if (std::find(values.begin(), values.end(), 1.0) != values.end()) continue;
                const double var = spread_of(values).variance;
                // A reading is never more uncertain than a full lab range (the penalty of a
                // reading not reached): a packing whose creep stage runs into the tertiary
                // regime would otherwise make the floor, and so the tolerance, hundreds of %
                // (a 4-stage creep set at S 0.8: floor 406 %, tolerance 575 %).
                ss_c += std::min(var, kUnreachedPenalty * kUnreachedPenalty);
                ++m_c;
            }
            if (m_c) {
                f.model_nrmse_per_curve.emplace_back(s.label, std::sqrt(ss_c / static_cast<double>(m_c)));
                const std::string kind = curve_kind(s.label);
                auto it = std::find_if(by_kind.begin(), by_kind.end(), [&](auto& k) { return k.first == kind; });
                if (it == by_kind.end()) it = by_kind.insert(by_kind.end(), {kind, {0.0, 0}});
                it->second.first += ss_c;
                it->second.second += m_c;
            }
            ss += ss_c;
            m += m_c;
        }
        f.model_nrmse = m ? std::sqrt(ss / static_cast<double>(m)) : 0.0;
        for (const auto& [kind, sm] : by_kind)
            f.model_nrmse_per_kind.emplace_back(kind, std::sqrt(sm.first / static_cast<double>(sm.second)));
    }
    f.tolerance_nrmse = std::sqrt(2.0 * f.model_nrmse * f.model_nrmse + f.lab_nrmse * f.lab_nrmse);
    return f;
}

}  // namespace triax::diagnose
