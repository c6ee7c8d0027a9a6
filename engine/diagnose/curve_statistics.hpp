#pragma once
// The curve toolkit shared by everything that puts curves of several runs together (the
// diagnosis's packing mean and noise floor, the ensembles of seeds): a sampled curve read
// at an abscissa, and the spread of values over runs.
//
// A curve is two equal-length vectors (x, y), x ascending; a shear curve's strain may step
// back a little at a platen reversal, so a reading is taken on the FIRST segment that
// brackets it: y(xq) = (1 - w) y[i-1] + w y[i], w = (xq - x[i-1]) / (x[i] - x[i-1]), i the
// first index with x[i] >= xq (a zero-length segment gives y[i]).
#include <optional>
#include <vector>

namespace triax::diagnose {

// y(xq) inside the curve: nullopt before x.front() or past x.back() (1e-15 slack), or for
// an empty curve.
std::optional<double> value_at(const std::vector<double>& x, const std::vector<double>& y, double xq);
// y(xq) with the curve's end values outside it; x not empty.
double value_at_clamped(const std::vector<double>& x, const std::vector<double>& y, double xq);

// Statistics of one quantity over runs (packings, seeds), the values taken in the order
// given. `variance` is the sample variance (n - 1): the scatter of a run estimated from n;
// 0 for one value. All NaN (n = 0) for no values.
struct Spread {
    int n = 0;
    double mean = 0.0, variance = 0.0, min = 0.0, max = 0.0;
    double std() const;
};
Spread spread_of(const std::vector<double>& values);

}  // namespace triax::diagnose
