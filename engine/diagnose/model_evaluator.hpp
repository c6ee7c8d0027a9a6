#pragma once
// The diagnosis's access to the forward model: unit-cube points of a model variant (the base
// plus a list of effects) in, normalised residuals against the lab readings out.
//  - One engine run per distinct physical point: runs are cached, so a change of a test
//    artefact (post-processing) or a repeated point costs nothing.
//  - Runs go out in batches through a SimulationBatch (threads here, MPI ranks in the CLI).
//  - A run that fails (an exploding or escaping particle, a shear that does not start) is
//    run again once on another packing (seed + kRetrySeedOffset); only a point whose retry
//    also fails scores as infinitely bad, and both counts reach the report.
//  - Test artefacts (seating, membrane) are applied to a run's curves, and with `polish`
//    their coordinates are optimised per run (they cost no run: profiled parameters).
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "engine/diagnose/calibration.hpp"
#include "engine/diagnose/effect.hpp"
#include "engine/diagnose/forward_model.hpp"
#include "engine/diagnose/residuals.hpp"
#include "engine/diagnose/simulation_batch.hpp"

namespace triax::diagnose {

// A model variant: the base plus effects; parameters laid out base first, then each
// effect's in this order.
struct Variant {
    std::vector<Effect> effects;
};

// The other packing a failed run is retried on (a prime, far from any seed a user picks).
inline constexpr std::uint64_t kRetrySeedOffset = 1000003;

class ModelEvaluator {
public:
    ModelEvaluator(const LabDataset& lab, const ForwardModel& model, SimulationBatch& batch, std::uint64_t seed);

    const std::vector<ResidualSeries>& layout() const { return layout_; }
    const std::vector<std::pair<std::size_t, std::size_t>>& ranges() const { return ranges_; }
    std::size_t readings() const { return ranges_.empty() ? 0 : ranges_.back().second; }
    const std::vector<ParameterSpec>& base_specs() const { return base_specs_; }
    const std::map<Effect, std::vector<ParameterSpec>>& effect_specs() const { return effect_specs_; }
    // Catalog effects the model cannot show on these data, with the model's reason.
    const std::vector<std::pair<Effect, std::string>>& not_offered() const { return not_offered_; }

    std::vector<ParameterSpec> specs_of(const Variant& v) const;
    UnitPoint nominal_unit(const std::vector<ParameterSpec>& specs) const;
    UnitPoint extended(UnitPoint u, Effect e) const;                       // u with e's nominal appended
    UnitPoint project(const Variant& from, const UnitPoint& u, const Variant& to) const;
    // Unit-cube coordinates of the variant's test artefacts (one parameter each).
    std::vector<std::pair<std::size_t, Effect>> artefact_coordinates(const Variant& v) const;

    // Residuals for a batch of points (empty vector: the run failed twice). With `polish`
    // the artefact coordinates of the points are replaced by their optimum.
    std::vector<std::vector<double>> residuals(const Variant& v, std::vector<UnitPoint>& batch, bool polish);
    // Curves of the variant at u with its artefacts applied (the run is cached).
    LabDataset curves(const Variant& v, const UnitPoint& u);
    // The same physical point on other packings: one residual per seed (empty if it failed).
    // Not cached with the calibration's runs (they are another specimen).
    std::vector<std::vector<double>> replicates(const Variant& v, const UnitPoint& u, const std::vector<std::uint64_t>& seeds);

    // Weight of each reading in every residual returned (fit_weights.hpp; empty: all 1).
    void set_reading_weights(std::vector<double> w) { weights_ = std::move(w); }
    // A returned residual without its weights; a reading not reached reads kUnreachedPenalty.
    std::vector<double> unweighted(std::vector<double> r) const;
    // Sum of squares of a run that reached no reading (every reading at the penalty).
    double unreached_sum_of_squares() const;

    int runs() const { return runs_.load(); }
    int failures() const { return failures_.load(); }     // points whose run and retry both failed
    int retried() const { return retried_.load(); }       // runs that failed once and were retried
    std::vector<std::string> failure_messages() const;    // distinct engine messages, first few
    // Called after every finished engine run with the total so far.
    void on_run(std::function<void(int)> f) { on_run_ = std::move(f); }

private:
    // One engine-batch run finished: the count and the driver's progress.
    void count_run() {
        const int n = ++runs_;
        if (on_run_) on_run_(n);
    }
    ModelPoint physical_point(const Variant& v, const UnitPoint& u, std::vector<double>& key) const;
    // Runs every point of `points` not in the cache (with one retry); fills the cache.
    void run_missing(const std::vector<ModelPoint>& points, const std::vector<std::vector<double>>& keys);
    std::vector<double> with_artefacts(const Variant& v, const LabDataset& physical, const UnitPoint& u) const;
    std::vector<double> polished(const Variant& v, const LabDataset& physical, UnitPoint& u) const;

    const ForwardModel& model_;
    SimulationBatch& batch_;
    std::uint64_t seed_;
    std::vector<ResidualSeries> layout_;
    std::vector<std::pair<std::size_t, std::size_t>> ranges_;
    std::vector<double> weights_;
    std::vector<ParameterSpec> base_specs_;
    std::map<Effect, std::vector<ParameterSpec>> effect_specs_;
    std::vector<std::pair<Effect, std::string>> not_offered_;
    // Engine output per physical point; a failed point maps to nullopt-like empty dataset
    // with failed_ set.
    std::map<std::vector<double>, LabDataset> cache_;
    std::map<std::vector<double>, bool> failed_;
    mutable std::mutex mutex_;
    std::vector<std::string> messages_;
    std::atomic<int> runs_{0}, failures_{0}, retried_{0};
    std::function<void(int)> on_run_;
};

}  // namespace triax::diagnose
