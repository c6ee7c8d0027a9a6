#pragma once
// Macro figures of lab shear curves, the way a lab engineer reads them: per confining
// pressure the peak deviator and its strain, the deviator at the last reading, the secant
// modulus E50 (to half the peak) and the largest dilatancy rate -d(eps_v)/d(eps_a); across
// pressures the Mohr-Coulomb envelope of the peaks and of the last readings,
//   sigma1 = N sigma3 + 2 c sqrt(N),  N = tan^2(45 deg + phi / 2),
// fitted by least squares on (sigma3, sigma1) (c = 0 with a single pressure). The diagnosis
// starts its base model from them (cohesionless when the envelope has no intercept) and
// reports them beside the fit.
#include <vector>

#include "engine/diagnose/lab_data.hpp"

namespace triax::diagnose {

struct ShearMacro {
    double confining_pa = 0.0;
    double q_peak_pa = 0.0;
    double strain_at_peak = 0.0;
    double q_last_pa = 0.0;
    double last_strain = 0.0;
    double e50_pa = 0.0;               // 0.5 q_peak / strain at 0.5 q_peak
    double max_dilatancy_rate = 0.0;   // max of -d eps_v / d eps_a (> 0: dilation)
};

struct LabMacro {
    std::vector<ShearMacro> shear;     // one per shear curve with deviator readings
    double peak_friction_angle_deg = 0.0;
    double peak_cohesion_pa = 0.0;
    double last_friction_angle_deg = 0.0;  // envelope of the last readings (residual / critical)
    double last_cohesion_pa = 0.0;
};

LabMacro lab_macro(const LabDataset& lab);

}  // namespace triax::diagnose
