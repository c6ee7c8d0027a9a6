#pragma once
// Effective number of readings and BIC. Readings along a curve are autocorrelated (the
// residual of a smooth misfit changes slowly), so counting every reading as independent
// would make any extra parameter look significant. Each series contributes
//   n_eff = n (1 - rho1) / (1 + rho1),  rho1 = lag-1 autocorrelation of its residual,
// (the AR(1) variance-inflation result), rho1 clamped to [0, 0.95]. The BIC of a model
// with k free parameters on the pooled normalised residual is
//   BIC = n_eff ln(RSS / n) + k ln(n_eff)
// with RSS / n the mean square per reading (the per-reading variance estimate; dividing
// RSS by n_eff would mix the two counts). Models are compared with one n_eff for all,
// taken from the best-fitting model's residual, so the comparison is on equal terms.
#include <cstddef>
#include <utility>
#include <vector>

namespace triax::diagnose {

double effective_readings(const std::vector<double>& residual);

// Sum of effective_readings over the series ranges of a stacked residual.
double effective_readings(const std::vector<double>& residual,
                          const std::vector<std::pair<std::size_t, std::size_t>>& ranges);

double residual_sum_of_squares(const std::vector<double>& residual);

double bic(double rss, std::size_t n, double n_eff, std::size_t k);

// Paired gains of a model change, in pooled NRMSE: the gain on the calibration's packing
// first, then per other packing without - with (the two runs of a pair share a packing, so
// its stick-slip history cancels; docs/diagnosis.md section 4).
std::vector<double> paired_gains(double own_gain, const std::vector<double>& without_elsewhere,
                                 const std::vector<double>& with_elsewhere);

// The mean of paired gains and their sample standard deviation across packings; a change
// is seen when the mean exceeds the spread.
struct PairedGainSummary {
    double mean = 0.0;
    double spread = 0.0;
    bool seen() const { return mean > spread; }
};
PairedGainSummary summarise_paired_gains(const std::vector<double>& gains);

// Whether a test artefact kept in the final model is named, from its step's figures with
// paired packings (two or more): it lowers BIC by more than kArtefactBicThreshold, its
// paired gain exceeds the gain's spread, and it lowers the misfit at every confining
// pressure (an apparatus artefact acts on every specimen). 6 is Kass and Raftery's
// "strong evidence" bound, against 10 ("very strong") for a physical effect: a lab expects
// apparatus corrections (ASTM D4767 prescribes the membrane's), not a missing physics.
inline constexpr double kArtefactBicThreshold = 6.0;
bool artefact_named(double delta_bic, const std::vector<double>& paired_gains,
                    const std::vector<std::pair<double, double>>& gain_by_confining);

// The median spread over sets of paired gains of two or more packings (0 if none): the gain
// a change must exceed to be seen.
double median_paired_spread(const std::vector<std::vector<double>>& gain_sets);

// A model change's gain on each confining pressure of one packing: per pressure, the RMS of
// the pooled normalised residual over that pressure's series without the change minus with
// it, in ascending pressure (Pa). `series_confining_pa[i]` is the pressure of
// `ranges[i]`. An apparatus artefact acts on every specimen tested, so its gain is positive
// on every pressure; a correction standing in for a shape the model lacks helps some
// pressures at the others' expense.
std::vector<std::pair<double, double>> gains_by_confining(const std::vector<double>& without, const std::vector<double>& with,
                                                          const std::vector<std::pair<std::size_t, std::size_t>>& ranges,
                                                          const std::vector<double>& series_confining_pa);

}  // namespace triax::diagnose
