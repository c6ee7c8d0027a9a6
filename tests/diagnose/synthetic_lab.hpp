#pragma once
// Synthetic "lab" datasets for the diagnosis tests: a forward model run with an effect
// switched on that the diagnosis is not told about, read at lab-like readings, with a
// smooth bedding (seating) closure at the start of loading and Gaussian measurement noise.
// The seating form here (soil strain lags the measured strain by s (1 - exp(-eps/0.3 s)))
// differs on purpose from the diagnosis's own sharp-offset artefact.
#include <cmath>
#include <random>

#include "engine/diagnose/diagnosis.hpp"
#include "engine/diagnose/forward_model.hpp"
#include "engine/diagnose/metrics.hpp"

namespace triax::diagnose::testing {

struct SyntheticLabOptions {
    double seating_strain = 0.004;
    double membrane_stiffness_pa = 0.0;  // adds K_m * eps to the measured deviator
    double deviator_noise_pa = 1500.0;
    double volumetric_noise = 2e-4;
    double creep_noise = 2e-5;
    std::uint64_t seed = 7;
    double shear_strain_step = 0.0025;  // readings of a shear curve: 0, step, ... up to
    int shear_readings = 61;            // shear_readings - 1 steps (lab-like: 0.25 % to 15 %)
};

// The loop's options on the analytic stand-in: a converged calibration and candidate fits
// (budget 24, refine 10, three candidates, three effects, one run per batch). The stand-in
// has no packing scatter, so only BIC guards against a candidate that merely out-calibrates
// the base; the product's defaults are set for DEM run cost and rely on the packing floor
// as well (docs/diagnosis.md section 5).
inline DiagnoseOptions analytic_method_options() {
    DiagnoseOptions o;
    o.budget_runs = 24;
    o.refine_runs = 10;
    o.max_candidates = 3;
    o.max_effects = 3;
    o.batch_runs = 1;
    o.concurrency = 1;
    return o;
}

inline double interpolate_at(const std::vector<double>& x, const std::vector<double>& y, double xq) {
    if (xq <= x.front()) return y.front();
    if (xq >= x.back()) return y.back();
    const auto j = static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), xq) - x.begin());
    const double w = (xq - x[j - 1]) / (x[j] - x[j - 1]);
    return (1 - w) * y[j - 1] + w * y[j];
}

inline LabDataset make_synthetic_lab(const ForwardModel& model, const ModelPoint& truth, const SyntheticLabOptions& o) {
    const LabDataset clean = model.simulate(truth, o.seed);
    std::mt19937_64 rng(o.seed);
    std::normal_distribution<double> nd;
    LabDataset lab;
    lab.name = "synthetic";
    int first_stage = 1 << 30;
    for (const auto& c : clean.curves)
        if (c.kind == CurveKind::Creep) first_stage = std::min(first_stage, c.stage);
    for (const auto& c : clean.curves) {
        LabCurve r;
        r.kind = c.kind;
        r.stage = c.stage;
        r.confining_pa = c.confining_pa;
        r.stress_level = c.stress_level;
        if (c.kind == CurveKind::Shear) {
            for (int i = 0; i < o.shear_readings; ++i) {
                const double eps = o.shear_strain_step * i;
                const double s = o.seating_strain;
                const double soil = s > 0 ? std::max(0.0, eps - s * (1 - std::exp(-eps / (0.3 * s)))) : eps;
                r.axial_strain.push_back(eps);
                r.deviator_pa.push_back(interpolate_at(c.axial_strain, c.deviator_pa, soil) +
                                        o.membrane_stiffness_pa * eps + o.deviator_noise_pa * nd(rng));
                r.volumetric_strain.push_back(interpolate_at(c.axial_strain, c.volumetric_strain, soil) +
                                              o.volumetric_noise * nd(rng));
            }
        } else {
            const double minutes[] = {0, 0.5, 1, 2, 4, 6, 10, 15, 20, 30, 45, 60, 90, 120, 180, 240,
                                      360, 480, 720, 960, 1200, 1500, 1800, 2000, 2400, 2700, 3000};
            for (double m : minutes) {
                const double t = 60.0 * m;
                r.time_s.push_back(t);
                const double eps = interpolate_at(c.time_s, c.axial_strain, t) +
                                   (c.stage == first_stage ? o.seating_strain : 0.0) + o.creep_noise * nd(rng);
                r.axial_strain.push_back(eps);
                r.axial_deformation_m.push_back(eps * 0.2);
            }
        }
        lab.curves.push_back(std::move(r));
    }
    return lab;
}

}  // namespace triax::diagnose::testing
