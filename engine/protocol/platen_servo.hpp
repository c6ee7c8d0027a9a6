#pragma once
// The stress-controlled platen (PFC-style servo): platen speed proportional to the stress
// error, the gain chosen so that one chunk of kChunk cycles closes 20 % of the error on the
// assumed skeleton stiffness, the speed capped at v_max. One servo for the consolidation
// (both platens) and the creep holds (top platen).
//
//   v = clamp(g (sigma_target - sigma_measured), -v_max, v_max),
//   g = 0.2 A / (k_skeleton dt kChunk)
//
// k_skeleton = 8 kn (about 8 contacts under a grain: the stiffness of a consolidated
// skeleton seen by a platen); v_max moves the platen 5 % of the specimen height in 2000
// steps. Both are fixed when the specimen is consolidated (PlatenServo::for_specimen).
// Sign: v > 0 moves the platen towards the specimen (compression).
#include <algorithm>

namespace triax::protocol {

class Specimen;

struct PlatenServo {
    static constexpr long kChunk = 50;  // cycles between servo updates
    double k_skeleton_n_m = 0.0;
    double v_max_m_s = 0.0;

    // From the specimen's grain stiffness, height and time step.
    static PlatenServo for_specimen(const Specimen& sp);

    // Platen speed (m/s, towards the specimen) for the stress error target - measured (Pa)
    // on the cross-section area (m^2) at time step dt (s).
    double velocity(double target_pa, double measured_pa, double area_m2, double dt_s) const {
        const double gain = 0.2 * area_m2 / (k_skeleton_n_m * dt_s * kChunk);
        return std::clamp(gain * (target_pa - measured_pa), -v_max_m_s, v_max_m_s);
    }
};

}  // namespace triax::protocol
