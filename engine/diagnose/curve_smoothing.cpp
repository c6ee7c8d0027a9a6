#include "engine/diagnose/curve_smoothing.hpp"

#include <cmath>
#include <stdexcept>

namespace triax::diagnose {

std::vector<double> smooth_over_relative_strain(const std::vector<double>& x, const std::vector<double>& y) {
    if (x.size() != y.size()) throw std::invalid_argument("smooth_over_relative_strain: x and y differ in length");
    std::vector<double> out(y.size());
    const std::size_t n = x.size();
    std::size_t lo = 0, hi = 0;  // window [lo, hi) over the ascending strains
    for (std::size_t i = 0; i < n; ++i) {
        const double h = kRelativeHalfWidth * x[i];
        if (!(h > 0.0)) {
            out[i] = y[i];
            continue;
        }
        while (lo < i && x[lo] <= x[i] - h) ++lo;
        if (hi < i + 1) hi = i + 1;
        while (hi < n && x[hi] < x[i] + h) ++hi;
        // Weighted straight-line fit through the window, read at x_i: a line stays exactly
        // a line even where the window is cut at the curve's last reading.
        double sw = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
        for (std::size_t k = lo; k < hi; ++k) {
            const double d = x[k] - x[i];
            const double w = 1.0 - std::abs(d) / h;
            if (w <= 0.0) continue;
            sw += w;
            sx += w * d;
            sy += w * y[k];
            sxx += w * d * d;
            sxy += w * d * y[k];
        }
        const double det = sw * sxx - sx * sx;
        out[i] = det > 1e-12 * sw * sxx ? (sxx * sy - sx * sxy) / det : y[i];
    }
    return out;
}

}  // namespace triax::diagnose
