#pragma once
// Parameters of the time-dependent contact law (rate_state_creep.hpp, docs/creep.md).
namespace triax::creep {

// The law's parameters, one set of defaults (docs/creep.md section 5, "Parameters"; reach: bench/README.md, "Rate-and-state contact creep").
// The scheme's `creep` section is these plus the stage schedule (protocol::CreepLawParameters);
// the JSON edge maps its fields one to one (server/io/scheme_fields.cpp).
struct RateStateParams {
    // Rate-and-state friction at frictional contacts (Dieterich-Ruina, aging law, b = m a):
    // slip rate v = (D_c / t_r) exp(-mu (1 - f) / a) (t_r / theta)^m, f = |Fs| / (mu Fn).
    double direct_effect_a = 0.03;        // a (-): the rate sensitivity of friction, 1e-4-0.1 (contacts 0.005-0.015)
    double critical_slip_m = 1.0e-5;      // D_c (m): slip that renews a contact's state, 0.1-100 um
    // m = b / a (-): the state's weight. Under a held load the slip rate falls as t^-m
    // (Singh-Mitchell's exponent): m = 1 is creep logarithmic in time, m < 1 a power of time
    // whose steady rate (a - b) rate-strengthening allows. 0.5-1.
    double state_exponent_m = 1.0;
    // Age of a contact whose state was renewed by slip (s): the youngest state, as after a
    // stage's loading ramp. A lab load step takes about a minute.
    double renewed_age_s = 60.0;
    // Age of a contact the specimen's preparation and consolidation formed, at the first
    // stage's loading (s): the consolidation's hold. A lab holds the consolidation until the
    // volume change stops, an hour or more for coarse fill; the first stage then creeps from
    // contacts that its loading moves, not from every contact of the specimen.
    double consolidated_age_s = 3600.0;
    // Stress corrosion of contact bonds: dDb/dt = b1 exp(b2 rho) when rho > threshold.
    double bond_corrosion_rate_b1_per_s = 1.0e-9;  // b1, 0 = no corrosion
    double bond_corrosion_b2 = 10.0;               // b2
    double bond_corrosion_threshold = 0.9;         // rho_th
};

}  // namespace triax::creep
