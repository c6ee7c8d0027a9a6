// Goodness-of-fit of a model curve against measured readings (see metrics.hpp).
// The model is interpolated linearly onto each measured abscissa; readings outside the
// model's abscissa range are dropped rather than extrapolated, because extrapolating a
// DEM curve past its last reading invents physics the run never produced.
#include "engine/diagnose/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace triax::diagnose {

namespace {

// Sort (x, y) pairs by x; stable so equal abscissae keep reading order.
void sort_by_abscissa(std::vector<double>& x, std::vector<double>& y) {
    if (std::is_sorted(x.begin(), x.end())) return;
    std::vector<std::size_t> order(x.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return x[a] < x[b]; });
    std::vector<double> xs(x.size()), ys(y.size());
    for (std::size_t k = 0; k < order.size(); ++k) {
        xs[k] = x[order[k]];
        ys[k] = y[order[k]];
    }
    x.swap(xs);
    y.swap(ys);
}

// Linear interpolation on sorted x; caller guarantees x.front() <= xq <= x.back().
double interpolate(const std::vector<double>& x, const std::vector<double>& y, double xq) {
    auto hi = std::lower_bound(x.begin(), x.end(), xq);
    if (hi == x.begin()) return y.front();
    if (hi == x.end()) return y.back();
    const std::size_t j = static_cast<std::size_t>(hi - x.begin());
    const double x0 = x[j - 1], x1 = x[j];
    if (x1 == x0) return y[j];
    const double w = (xq - x0) / (x1 - x0);
    return (1.0 - w) * y[j - 1] + w * y[j];
}

}  // namespace

CurveMetrics compare_curve(const std::vector<double>& x_model, const std::vector<double>& y_model,
                           const std::vector<double>& x_lab, const std::vector<double>& y_lab) {
    if (x_model.size() != y_model.size())
        throw std::invalid_argument("compare_curve: model abscissa has " + std::to_string(x_model.size()) +
                                    " values but model ordinate has " + std::to_string(y_model.size()));
    if (x_lab.size() != y_lab.size())
        throw std::invalid_argument("compare_curve: lab abscissa has " + std::to_string(x_lab.size()) +
                                    " values but lab ordinate has " + std::to_string(y_lab.size()));

    // Non-finite model values (a failed or cut run) are removed, not propagated as NaN metrics.
    std::vector<double> xm, ym;
    xm.reserve(x_model.size());
    ym.reserve(y_model.size());
    for (std::size_t k = 0; k < x_model.size(); ++k)
        if (std::isfinite(x_model[k]) && std::isfinite(y_model[k])) {
            xm.push_back(x_model[k]);
            ym.push_back(y_model[k]);
        }
    sort_by_abscissa(xm, ym);

    CurveMetrics m;
    if (xm.empty()) {
        m.dropped = x_lab.size();
        return m;
    }
    const double lo = xm.front(), hi = xm.back();
    for (std::size_t k = 0; k < x_lab.size(); ++k) {
        const double xq = x_lab[k];
        if (!std::isfinite(xq) || !std::isfinite(y_lab[k]) || xq < lo || xq > hi) {
            ++m.dropped;
            continue;
        }
        const double model = interpolate(xm, ym, xq);
        m.points.push_back({xq, model, y_lab[k], model - y_lab[k]});
    }
    m.n = m.points.size();
    if (m.n == 0) return m;

    double ss_res = 0.0, lab_sum = 0.0, lab_min = m.points.front().lab, lab_max = lab_min;
    for (const auto& p : m.points) {
        ss_res += p.residual * p.residual;
        lab_sum += p.lab;
        lab_min = std::min(lab_min, p.lab);
        lab_max = std::max(lab_max, p.lab);
        m.max_error = std::max(m.max_error, std::abs(p.residual));
    }
    const double lab_mean = lab_sum / static_cast<double>(m.n);
    double ss_tot = 0.0;
    for (const auto& p : m.points) ss_tot += (p.lab - lab_mean) * (p.lab - lab_mean);

    m.rmse = std::sqrt(ss_res / static_cast<double>(m.n));
    const double range = lab_max - lab_min;
    m.nrmse = range > 0.0 ? m.rmse / range : 0.0;
    // A flat lab curve has no variance to explain: R^2 is 1 for an exact match, else 0.
    m.r2 = ss_tot > 0.0 ? 1.0 - ss_res / ss_tot : (ss_res == 0.0 ? 1.0 : 0.0);
    return m;
}

}  // namespace triax::diagnose
