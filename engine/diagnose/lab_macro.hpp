#pragma once
// Macro figures of lab shear curves, the way a lab engineer reads them: per confining
// pressure the peak deviator and its strain, the deviator at the last reading, the secant
// modulus E50 (to half the peak) and the largest dilatancy rate -d(eps_v)/d(eps_a); across
// pressures the Mohr-Coulomb envelope of the peaks and of the last readings,
//   sigma1 = N sigma3 + 2 c sqrt(N),  N = tan^2(45 deg + phi / 2),
// fitted by least squares on (sigma3, sigma1) (c = 0 with a single pressure). The diagnosis
// starts its base model from them (cohesionless when the envelope has no intercept) and
// reports them beside the fit.
#include <limits>
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

// A creep stage's creep per decade of time: the least-squares slope of the axial strain
// against log10 t over the readings from the first minute on (the loading ramp's own
// readings excluded); at least three readings there, else the stage has none.
struct CreepMacro {
    double confining_pa = 0.0;
    int stage = 0;
    double stress_level = 0.0;        // S as the lab gave it (0: not given)
    double strain_per_decade = 0.0;   // [-], compression positive
};

// Strain per decade of a (time s, strain) creep record over [t0_s, t1_s]; 0 with fewer
// than three readings there.
double creep_strain_per_decade(const std::vector<double>& time_s, const std::vector<double>& strain, double t0_s = 60.0,
                               double t1_s = std::numeric_limits<double>::infinity());

struct LabMacro {
    std::vector<ShearMacro> shear;     // one per shear curve with deviator readings
    std::vector<CreepMacro> creep;     // one per creep stage with axial strain readings
    double peak_friction_angle_deg = 0.0;
    double peak_cohesion_pa = 0.0;
    double last_friction_angle_deg = 0.0;  // envelope of the last readings (residual / critical)
    double last_cohesion_pa = 0.0;
};

LabMacro lab_macro(const LabDataset& lab);

}  // namespace triax::diagnose
