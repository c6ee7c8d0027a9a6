// Kind weights of the fit (see fit_weights.hpp).
#include "engine/diagnose/fit_weights.hpp"

#include <algorithm>
#include <limits>

namespace triax::diagnose {

KindWeights kind_weights(const NoiseFloor& noise) {
    if (noise.model_nrmse_per_kind.size() < 2) return {};
    KindWeights scatter;
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
    for (const auto& [kind, s] : noise.model_nrmse_per_kind) {
        const double k = std::max({s, noise.lab_nrmse, kMinimumKindScatter});
        scatter.emplace_back(kind, k);
        lo = std::min(lo, k), hi = std::max(hi, k);
    }
    if (!(hi > kReweighRatio * lo)) return {};
    for (auto& [kind, s] : scatter) s = std::min(1.0, lo / s);
    return scatter;
}

std::vector<double> reading_weights(const std::vector<ResidualSeries>& layout, const KindWeights& weights) {
    if (weights.empty()) return {};
    std::vector<double> w;
    for (const auto& s : layout) {
        double k = 1.0;
        for (const auto& [kind, v] : weights)
            if (kind == curve_kind(s.label)) k = v;
        w.insert(w.end(), s.x.size(), k);
    }
    return w;
}

std::vector<double> unweighted(std::vector<double> r, const std::vector<double>& weights) {
    if (weights.size() != r.size()) return r;
    for (std::size_t i = 0; i < r.size(); ++i)
        r[i] = r[i] == kUnreachedPenalty * weights[i] ? kUnreachedPenalty : r[i] / weights[i];
    return r;
}

}  // namespace triax::diagnose
