#pragma once
// The residual of a model against lab readings, as one fixed-length vector the calibration
// can work on, with each reading labelled by curve and phase so errors can be reported per
// phase. Each series is normalised by the range of its lab readings (NRMSE units), so a
// deviator in Pa, a volumetric strain and a creep strain can be pooled.
#include <string>
#include <vector>

#include "engine/diagnose/diagnosis.hpp"
#include "engine/diagnose/lab_data.hpp"

namespace triax::diagnose {

// Creep curves are compared on axial strain when the lab gives it, else on axial
// deformation (m) - GDS exports often carry only the displacement.
// A creep stage's curve is split in two: its deformation at loading (the stage's first
// reading: the instant response, one reading per stage, pooled per pressure as the series
// "instant@100kPa", Quantity::CreepInstant, x = stage number) and the creep after it (the
// series "creep-2@100kPa": readings after the first, counted from it). The instant part is
// a loading response (the shear curve's business, and on a ~200-grain specimen its packing
// scatter is several times a stage's creep); normalised together, a stage's small creep
// range made any instant misfit look like 100s of % and hid the creep's shape.
enum class Quantity { Deviator, Volumetric, CreepStrain, CreepDeformation, CreepInstant };

// Phase of each reading, decided from the lab curve alone so that every model is scored
// on the same split:
//  deviator vs axial strain: pre_peak up to the (smoothed) peak of q, post_peak after it;
//  volumetric vs axial strain: contraction up to the largest contraction, dilation after;
//  creep strain vs time (after the stage's first reading): primary while the strain rate
//  is above twice its minimum and falling, steady around the minimum, tertiary once it has
//  risen back above twice the minimum (and stays there);
//  instant series: instant.
struct ResidualSeries {
    std::string label;     // "stress_strain@100kPa", "volumetric@100kPa", "creep-2@100kPa"
    std::string unit;      // SI unit of lab/model: "Pa", "-" or "m"
    Quantity quantity = Quantity::Deviator;
    int stage = 0;
    double confining_pa = 0.0;
    double scale = 1.0;    // range of the lab readings; residual / scale is what is pooled
    std::vector<double> x, lab;
    std::vector<std::string> phase;
    // Creep series: lab and model readings are counted from their value at this time (s).
    double reference_time = 0.0;
    // Instant series: per reading (stage) the time of that stage's first reading (s), and
    // whether the stages were read as strain (else deformation, m).
    std::vector<double> stage_time;
    bool instant_as_strain = true;
};

// Lab side of the residual, built once per dataset. Throws std::invalid_argument when the
// dataset has no usable curve (naming what is missing).
std::vector<ResidualSeries> residual_layout(const LabDataset& lab);

// The residual of a reading the model does not reach (curve missing, shorter strain or time
// range, non-finite value): a full lab range, so the vector length never changes between
// models. Error figures count such readings apart from the misfit (is_unreached).
inline constexpr double kUnreachedPenalty = 1.0;
inline bool is_unreached(double normalised_residual) { return normalised_residual == kUnreachedPenalty; }

// Normalised residuals (model - lab) / scale, stacked in layout order; unreached readings
// get kUnreachedPenalty.
// If `model_values` is given it receives the model value at each reading (NaN if missing).
std::vector<double> normalised_residual(const std::vector<ResidualSeries>& layout, const LabDataset& predicted,
                                        std::vector<std::vector<double>>* model_values = nullptr);

// RMSE / NRMSE per series ("all") and per phase, from a stacked normalised residual, over
// the readings the model reached; the others are counted in n_unreached.
std::vector<PhaseError> phase_errors(const std::vector<ResidualSeries>& layout, const std::vector<double>& residual);

// Index range [begin, end) of each series in the stacked vector.
std::vector<std::pair<std::size_t, std::size_t>> series_ranges(const std::vector<ResidualSeries>& layout);

}  // namespace triax::diagnose
