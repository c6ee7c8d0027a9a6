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
inline std::vector<TimeDeformation> translate_stage(const std::vector<TimeDeformation>& raw, double stage_start_time,
                                                    double stage_end_time, double deformation_before) {
    std::vector<TimeDeformation> out;
    for (const auto& r : raw)
        if (r.time >= stage_start_time && r.time <= stage_end_time)
            out.push_back({r.time - stage_start_time, r.deformation - deformation_before});
    return out;
}

}  // namespace triax::creep
