#pragma once
// The strength envelope of a set of shear curves in lab units, as a lab report gives it:
// the Mohr circle at failure (the peak deviator) of each confining pressure and the
// Mohr-Coulomb fit through them, c' (kPa) and phi' (deg), with its line in p'-q.
// The fit is the engine's (diagnose::lab_macro: least squares of sigma1 on sigma3,
// sigma1 = N sigma3 + 2 c' sqrt(N), N = tan^2(45 deg + phi'/2); no negative c'; c' = 0 with
// one pressure), the one the diagnosis starts its base model from; nothing else fits it.
// Effective stresses (drained test, no pore pressure), compression positive.
#include <nlohmann/json.hpp>

#include "engine/diagnose/lab_data.hpp"

namespace triax::io {

// {"circles":[{"sigma3_kPa","sigma1_kPa","q_peak_kPa","p_kPa","axial_strain_at_peak_pct"}],
//  "friction_angle_deg","cohesion_kPa","n_pressures","p_q_line":{"slope","intercept_kPa"}}
// or, without a shear curve that has deviator readings, {"circles":[], ... null}.
nlohmann::json strength_envelope_json(const diagnose::LabDataset& curves);

// The Mohr-Coulomb line in p'-q for triaxial compression (p' = (sigma1 + 2 sigma3) / 3):
// q = M p' + k with M = 6 sin phi' / (3 - sin phi'), k = 6 c' cos phi' / (3 - sin phi').
struct PqLine { double slope = 0.0; double intercept_kpa = 0.0; };
PqLine mohr_coulomb_pq_line(double friction_angle_deg, double cohesion_kpa);

}  // namespace triax::io
