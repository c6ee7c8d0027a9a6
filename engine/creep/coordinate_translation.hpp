#pragma once
// Coordinate translation of the paper (Boltzmann superposition, Chen's method): stepwise
// loading on one specimen becomes one creep curve per stage by moving the origin of each
// stage to its loading instant: t' = t - t_k, and deformation counted from the level just
// before stage k was loaded, d' = d - d(t_k^-). The instantaneous part (the jump at
// loading) stays in d'(0). Units: whatever the caller uses (s and m in the engine).
#include <vector>

namespace triax::creep {

struct TimeDeformation {
    double time = 0.0;
    double deformation = 0.0;
};

// `raw`: cumulative readings of the whole multi-stage test; stage k starts at
// stage_start_time and deformation_before is the deformation just before its load step.
// Two readings at stage_start_time (the end of stage k-1 and the reading after the load
// step) are told apart by order: the stage starts at the last of them.
inline std::vector<TimeDeformation> translate_stage(const std::vector<TimeDeformation>& raw, double stage_start_time,
                                                    double stage_end_time, double deformation_before) {
    std::size_t first = raw.size();
    for (std::size_t k = 0; k < raw.size(); ++k) {
        if (raw[k].time <= stage_start_time) first = k;
        else if (first == raw.size()) { first = k; break; }
        else break;
    }
    std::vector<TimeDeformation> out;
    for (std::size_t k = first; k < raw.size() && raw[k].time <= stage_end_time; ++k)
        if (raw[k].time >= stage_start_time) out.push_back({raw[k].time - stage_start_time, raw[k].deformation - deformation_before});
    return out;
}

}  // namespace triax::creep
