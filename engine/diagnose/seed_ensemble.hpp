#pragma once
// An ensemble of seeds: one scheme run on several packings, summarised as the mean and band
// of every curve and the share of seeds in each creep regime. A single seed's S = 0.8 stage
// is tertiary or not by the luck of its packing; the ensemble gives the probability.
// Statistics take the members in seed order, with the curve toolkit (curve_statistics.hpp):
// a member contributes at a grid point it reaches.
#include <cstdint>
#include <string>
#include <vector>

namespace triax::diagnose {

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

// Statistic of one quantity at the points of a grid: over the members that reach each point
// (std: the sample standard deviation; NaN where no member reaches).
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

}  // namespace triax::diagnose
