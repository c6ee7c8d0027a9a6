#pragma once
// Goodness-of-fit between a model curve and a measured curve, aligned on the measured
// abscissa by linear interpolation of the model (no extrapolation: readings outside the
// model's range are dropped and counted).
#include <vector>

namespace triax::diagnose {

struct AlignedPoint { double x, model, lab, residual; };  // residual = model - lab

struct CurveMetrics {
    std::size_t n = 0;            // aligned readings
    std::size_t dropped = 0;      // readings outside the model's abscissa range
    double rmse = 0.0;
    double nrmse = 0.0;           // rmse / (max(lab) - min(lab)); 0 if the range is 0
    double r2 = 0.0;              // 1 - SS_res / SS_tot
    double max_error = 0.0;       // max |residual|
    std::vector<AlignedPoint> points;
};

// x_model must be sorted ascending (it is made so if not); y_* in the same unit.
CurveMetrics compare_curve(const std::vector<double>& x_model, const std::vector<double>& y_model,
                           const std::vector<double>& x_lab, const std::vector<double>& y_lab);

}  // namespace triax::diagnose
