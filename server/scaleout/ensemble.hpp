#pragma once
// Ensemble runs: one scheme at several seeds (packings), summarised as the mean and band of
// every curve and the share of seeds in each creep regime. A single seed's S = 0.8 stage is
// tertiary or not by the luck of its packing; the ensemble gives the probability.
//
// A member travels as bytes (a scale-out task, task_runner.hpp): the seed in, the curves and
// the run's own regime flags (engine/protocol/creep_regime.hpp) out, so the members can run
// on threads or MPI ranks with the same result. Statistics take the members in seed order.
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/protocol/test_scheme.hpp"
#include "server/scaleout/task_runner.hpp"

namespace triax::scaleout {

struct MemberStage {
    int stage = 0;
    double stress_level = 0.0;  // q / q_f
    bool accelerating = false;  // tertiary creep (the run's flag)
    bool converged = false;
    bool ruptured = false;
    std::vector<double> time_s;        // stage time (translated curve)
    std::vector<double> axial_strain;  // -, compression positive
};

struct EnsembleMember {
    std::uint64_t seed = 0;
    bool ok = false;
    std::string error;  // when not ok
    double q_failure_pa = 0.0;
    double axial_strain_at_failure = 0.0;
    std::vector<double> axial_strain, deviator_pa, volumetric_strain;  // the shear curve
    std::vector<MemberStage> stages;
};

// Seeds "1-8", "3", "1,4,9-12": ascending, without repeats. Throws std::invalid_argument.
std::vector<std::uint64_t> parse_seed_list(std::string_view text);

// The task of one member and the handler that runs it (the whole protocol of `scheme`
// at the task's seed).
std::string member_task(std::uint64_t seed);
TaskHandler member_handler(const protocol::TestScheme& scheme);
// The same, stopping when `cancel_requested()` turns true: polled before a member starts
// and between the engine's increments (protocol::RunObserver::cancel_requested). A member
// so stopped throws MemberCancelled (its TaskResult is not ok).
struct MemberCancelled : std::runtime_error {
    MemberCancelled() : std::runtime_error("member cancelled") {}
};
TaskHandler member_handler(const protocol::TestScheme& scheme, std::function<bool()> cancel_requested);
// A task's result read back (a failed task: ok = false with its message).
EnsembleMember member_from_result(std::uint64_t seed, const TaskResult& result);

// Statistic of one quantity at the points of a grid: over the members that reach each point.
struct Band {
    std::vector<int> n;
    std::vector<double> mean, std, min, max;
};

struct CreepStageSummary {
    int stage = 0;
    double stress_level_mean = 0.0;
    int reached = 0;       // members that ran this stage
    double share_accelerating = 0.0, share_converged = 0.0, share_unsettled = 0.0, share_ruptured = 0.0;  // of `reached`
    std::vector<double> time_s;  // grid
    Band axial_strain;
};

struct EnsembleSummary {
    std::string scheme_name;
    std::vector<EnsembleMember> members;  // in seed order
    int ok = 0;
    Band q_failure_pa;                    // one point
    Band axial_strain_at_failure;
    std::vector<double> shear_axial_strain;  // grid from 0 to the longest curve
    Band deviator_pa, volumetric_strain;
    std::vector<CreepStageSummary> stages;
};

// Grids: 101 shear strains from 0 to the longest member's last strain; per creep stage,
// t = 0 and 100 times spaced in log from the first reading to the longest stage. A member
// contributes at a grid point it reaches (linear interpolation between its readings).
EnsembleSummary summarise_ensemble(std::string scheme_name, std::vector<EnsembleMember> members);

// ensemble.json (lab units: kPa, %, min; compression positive). With `with_curves` the
// bands are included (the file); without, the summary printed on stdout.
nlohmann::json ensemble_to_json(const EnsembleSummary& s, bool with_curves);
// shear_band.csv and creep_band.csv.
std::string shear_band_csv(const EnsembleSummary& s);
std::string creep_band_csv(const EnsembleSummary& s);

}  // namespace triax::scaleout
