// Effective readings, BIC and paired gains (formulas in model_selection.hpp).
#include "engine/diagnose/model_selection.hpp"

#include "engine/diagnose/residuals.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace triax::diagnose {

double effective_readings(const std::vector<double>& r) {
    const std::size_t n = r.size();
    if (n < 3) return static_cast<double>(n);
    double mean = 0.0;
    for (double v : r) mean += v;
    mean /= static_cast<double>(n);
    double c0 = 0.0, c1 = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        c0 += (r[i] - mean) * (r[i] - mean);
        if (i + 1 < n) c1 += (r[i] - mean) * (r[i + 1] - mean);
    }
    // A constant residual has no noise to estimate correlation from: treat as fully correlated.
    const double rho = c0 > 0.0 ? std::clamp(c1 / c0, 0.0, 0.95) : 0.95;
    return std::max(1.0, static_cast<double>(n) * (1.0 - rho) / (1.0 + rho));
}

double effective_readings(const std::vector<double>& r, const std::vector<std::pair<std::size_t, std::size_t>>& ranges) {
    double total = 0.0;
    for (const auto& [a, b] : ranges) {
        if (b > r.size() || a > b) throw std::out_of_range("effective_readings: series range outside the residual");
        total += effective_readings(std::vector<double>(r.begin() + static_cast<long>(a), r.begin() + static_cast<long>(b)));
    }
    return total;
}

double residual_sum_of_squares(const std::vector<double>& r) {
    double s = 0.0;
    for (double v : r) s += v * v;
    return s;
}

double bic(double rss, std::size_t n, double n_eff, std::size_t k) {
    if (n == 0 || n_eff <= 1.0) throw std::invalid_argument("bic: needs more than one effective reading");
    // Floor on the mean square: an exact fit must not give -infinity.
    const double ms = std::max(rss / static_cast<double>(n), 1e-300);
    return n_eff * std::log(ms) + static_cast<double>(k) * std::log(n_eff);
}

std::vector<double> paired_gains(double own_gain, const std::vector<double>& without_elsewhere,
                                 const std::vector<double>& with_elsewhere) {
    std::vector<double> g{own_gain};
    for (std::size_t k = 0; k < with_elsewhere.size() && k < without_elsewhere.size(); ++k)
        g.push_back(without_elsewhere[k] - with_elsewhere[k]);
    return g;
}

PairedGainSummary summarise_paired_gains(const std::vector<double>& gains) {
    PairedGainSummary s;
    if (gains.empty()) return s;
    for (double g : gains) s.mean += g / static_cast<double>(gains.size());
    double var = 0.0;
    for (double g : gains) var += (g - s.mean) * (g - s.mean);
    s.spread = std::sqrt(var / static_cast<double>(std::max<std::size_t>(1, gains.size() - 1)));
    return s;
}

bool artefact_named(double delta_bic, const std::vector<double>& paired_gains,
                    const std::vector<std::pair<double, double>>& gain_by_confining) {
    const bool every_pressure = std::all_of(gain_by_confining.begin(), gain_by_confining.end(),
                                            [](const auto& g) { return g.second > 0.0; });
    return delta_bic < -kArtefactBicThreshold && summarise_paired_gains(paired_gains).seen() && every_pressure;
}

double median_paired_spread(const std::vector<std::vector<double>>& gain_sets) {
    std::vector<double> spreads;
    for (const auto& g : gain_sets)
        if (g.size() >= 2) spreads.push_back(summarise_paired_gains(g).spread);
    if (spreads.empty()) return 0.0;
    std::sort(spreads.begin(), spreads.end());
    const std::size_t m = spreads.size() / 2;
    return spreads.size() % 2 ? spreads[m] : 0.5 * (spreads[m - 1] + spreads[m]);
}

std::vector<std::pair<double, double>> gains_by_confining(const std::vector<double>& without, const std::vector<double>& with,
                                                          const std::vector<std::pair<std::size_t, std::size_t>>& ranges,
                                                          const std::vector<double>& series_confining_pa) {
    if (series_confining_pa.size() != ranges.size())
        throw std::invalid_argument("gains_by_confining: one confining pressure per series range");
    struct Sums {
        double without = 0.0, with = 0.0;
        std::size_t n = 0;
    };
    std::map<double, Sums> by_pressure;
    for (std::size_t s = 0; s < ranges.size(); ++s) {
        const auto [a, b] = ranges[s];
        if (b > without.size() || b > with.size() || a > b)
            throw std::out_of_range("gains_by_confining: series range outside the residual");
        Sums& p = by_pressure[series_confining_pa[s]];
        for (std::size_t i = a; i < b; ++i) {
            // A reading either run did not reach is left out of both.
            if (is_unreached(without[i]) || is_unreached(with[i])) continue;
            p.without += without[i] * without[i];
            p.with += with[i] * with[i];
            ++p.n;
        }
    }
    std::vector<std::pair<double, double>> out;
    for (const auto& [pa, p] : by_pressure) {
        if (p.n == 0) continue;
        const double n = static_cast<double>(p.n);
        out.emplace_back(pa, std::sqrt(p.without / n) - std::sqrt(p.with / n));
    }
    return out;
}

}  // namespace triax::diagnose
