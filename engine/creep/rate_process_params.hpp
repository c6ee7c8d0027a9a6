#pragma once
// Parameters of the time-dependent contact law (rate_process_creep.hpp, docs/creep.md).
namespace triax::creep {

// The law's parameters, one set of defaults: the paper's calibration (docs/creep.md). The
// scheme's `creep` section is these plus the stage schedule (protocol::CreepLawParameters);
// the JSON edge maps its fields one to one (server/io/scheme_json.cpp).
struct RateProcessParams {
    // Rate process: slip rate v = v0 exp(-dE/kT) sinh(f / f_ref) on the mobilised friction
    // ratio f, lumped as v = A sinh(beta f).
    double slip_rate_a_m_s = 5.0e-21;     // A (m/s): rate at sliding ~ A e^beta / 2 = 2.7e-8 m/s
    double slip_beta = 30.0;              // beta = mu / a of rate-and-state friction
    // Delayed-slip capacity s_eq = s_h f / (1 - f + eps).
    double slip_hardening_length_m = 2.0e-6;  // s_h
    double capacity_offset = 0.5;             // eps: capacity at sliding is s_h / eps
    // Contact aging: a contact held for a stage (or the consolidation) bears this rise of
    // its mobilisation before it creeps again (static friction grows with hold time).
    double aging_margin = 0.2;
    // Asperity wear by creep slip: D = D_max (1 - exp(-slip / s_w)), friction mu (1 - D).
    double wear_length_m = 20.0e-6;       // s_w, 0 = no wear
    double wear_max = 0.5;                // D_max
    // Stress corrosion of contact bonds: dDb/dt = b1 exp(b2 rho) when rho > threshold.
    double bond_corrosion_rate_b1_per_s = 1.0e-9;  // b1, 0 = no corrosion
    double bond_corrosion_b2 = 10.0;               // b2
    double bond_corrosion_threshold = 0.9;         // rho_th
};

}  // namespace triax::creep
