#include "engine/diagnose/curve_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace triax::diagnose {

namespace {

// Reading on segment (i - 1, i).
double on_segment(const std::vector<double>& x, const std::vector<double>& y, std::size_t i, double xq) {
    if (x[i] == x[i - 1]) return y[i];
    const double w = std::clamp((xq - x[i - 1]) / (x[i] - x[i - 1]), 0.0, 1.0);
    return (1.0 - w) * y[i - 1] + w * y[i];
}

}  // namespace

std::optional<double> value_at(const std::vector<double>& x, const std::vector<double>& y, double xq) {
    if (x.empty() || xq > x.back() + 1e-15 || xq < x.front() - 1e-15) return std::nullopt;
    if (xq <= x.front()) return y.front();
    for (std::size_t i = 1; i < x.size(); ++i)
        if (x[i] >= xq) return on_segment(x, y, i, xq);
    return y.back();
}

double value_at_clamped(const std::vector<double>& x, const std::vector<double>& y, double xq) {
    if (xq <= x.front()) return y.front();
    for (std::size_t i = 1; i < x.size(); ++i)
        if (x[i] >= xq) return on_segment(x, y, i, xq);
    return y.back();
}

double Spread::std() const { return std::sqrt(variance); }

Spread spread_of(const std::vector<double>& values) {
    Spread s;
    s.n = static_cast<int>(values.size());
    if (values.empty()) {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        s.mean = s.variance = s.min = s.max = nan;
        return s;
    }
    double sum = 0.0;
    for (double v : values) sum += v;
    s.mean = sum / static_cast<double>(values.size());
    double ss = 0.0;
    for (double v : values) ss += (v - s.mean) * (v - s.mean);
    s.variance = values.size() > 1 ? ss / static_cast<double>(values.size() - 1) : 0.0;
    s.min = *std::min_element(values.begin(), values.end());
    s.max = *std::max_element(values.begin(), values.end());
    return s;
}

}  // namespace triax::diagnose
