#pragma once
// Calibration of model parameters to a residual vector, on a budget of model runs.
//
// Algorithm (DEcalioc-like: space-filling design, surrogate, refinement on real runs):
//  1. Parameters are mapped to the unit cube (log scale where ParameterSpec says so).
//  2. Design: the start point plus a seeded Latin hypercube of `design_runs` points.
//  3. Refinement, until the budget is spent or the trust radius collapses: a local
//     linear surrogate of the residual vector r(u) ~ r(u*) + J (u - u*) is fitted by
//     Gaussian-weighted least squares (width = trust radius h) to every run made so far
//     around the best point u*; Levenberg-Marquardt steps on that surrogate, one per
//     damping value in the batch, are run for real; h grows by 1.5 after an improvement
//     and halves otherwise. Regression over scattered runs instead of finite differences
//     because DEM output is rough at small parameter changes. After a batch that found
//     nothing better, the next batch also holds compass probes (+-h along one axis,
//     axes in turn): on a jagged objective the surrogate's direction can be wrong, and a
//     pattern search on real runs still makes progress (it needs no gradient).
//  Profiled coordinates (settings.profiled): parameters the evaluator optimises itself for
//  free at every point (test artefacts applied to a model run as post-processing). The
//  evaluator writes its optimum into the point; the surrogate and the steps act on the
//  other coordinates only (variable projection), so an artefact cannot pull the
//  physical parameters away to mimic it.
//     With local_starts > 1 the steps of a batch go out from the best runs of several
//     separated basins (multi-start): on DEM data the best run of a small design can sit in
//     a basin where the base parameters mimic a missing effect, and a better basin found by
//     a probe would otherwise get no step while it is second (docs/diagnosis.md 8.9).
//  4. Uncertainty: Cov(u) = s^2 (J^T J)^-1 (n / n_eff), s^2 = RSS / (n - k), mapped to
//     parameter units by the derivative of the unit-cube map; the n / n_eff factor
//     accounts for correlated readings along a curve.
// Runs of one batch are independent, so the evaluator may run them concurrently.
// The interface uses std::vector, not Eigen types: the engine may be compiled with
// -march=native (TRIAX_NATIVE) and its callers may not be, and Eigen objects allocated
// under one alignment setting must not be freed under another.
#include <cstdint>
#include <functional>
#include <vector>

#include "engine/diagnose/effect.hpp"

namespace triax::diagnose {

// Residual vectors for a batch of unit-cube points; an empty vector marks a failed run.
// The evaluator may overwrite the profiled coordinates of the points with their optimum.
using UnitPoint = std::vector<double>;
using BatchEvaluator = std::function<std::vector<std::vector<double>>(std::vector<UnitPoint>&)>;

struct CalibrationSettings {
    int design_runs = 12;       // Latin hypercube points (0: start point and refinement only)
    int refine_runs = 12;       // real runs spent on refinement
    int batch = 2;              // runs per refinement batch (different damping values)
    double initial_radius = 0.25;  // trust radius in unit-cube coordinates
    std::uint64_t seed = 1;
    UnitPoint start;            // starting point in the unit cube (required)
    // Extra design points placed +-radius along each axis around the start point (useful
    // when refining from a previous optimum, where a space-filling design would waste runs).
    bool axial_design = false;
    // Further design points chosen by the caller (run with the start point).
    std::vector<UnitPoint> extra_design;
    // Multi-start refinement: each batch's surrogate steps are spread over the best run and
    // the best runs of up to local_starts - 1 other basins (runs at least `separation` away,
    // in the max-norm over the stepped coordinates, from every better start), each with its
    // own local surrogate. 1: the best run only.
    int local_starts = 1;
    double separation = 0.25;
    // Coordinates the evaluator optimises itself (empty: none); not stepped, not probed.
    std::vector<bool> profiled;
    // Runs already made on the same parameter space (a previous calibration of the same
    // model): they join the surrogate fits and the choice of the best point, cost nothing
    // and are not counted in `runs`.
    const struct CalibrationResult* history = nullptr;
};

struct CalibrationResult {
    UnitPoint best;                       // unit-cube optimum
    std::vector<double> residual;         // residual at the optimum
    double rss = 0.0;
    std::vector<double> jacobian;         // d residual / d u at the optimum (surrogate),
                                          // column-major residual.size() x best.size()
    std::vector<UnitPoint> points;        // every run, in order
    std::vector<double> point_rss;        // RSS per run (infinity if it failed)
    std::vector<std::vector<double>> point_residuals;  // residual per run (empty if it failed)
    int runs = 0;
};

// `progress(runs_done)` is called after each batch and may throw to cancel.
CalibrationResult calibrate(const BatchEvaluator& evaluate, const CalibrationSettings& settings,
                            const std::function<void(int)>& progress = {});

// Unit cube <-> parameter values.
double to_parameter(const ParameterSpec& spec, double u);
double to_unit(const ParameterSpec& spec, double value);
double parameter_derivative(const ParameterSpec& spec, double u);  // d value / d u

// 1-sigma standard deviations of the parameters from a calibration result.
std::vector<double> parameter_std(const std::vector<ParameterSpec>& specs, const CalibrationResult& result,
                                  double n_effective);

// Seeded Latin hypercube in [0,1]^k (one stratum per point and axis, random inside it).
std::vector<UnitPoint> latin_hypercube(int points, int dimensions, std::uint64_t seed);

}  // namespace triax::diagnose
