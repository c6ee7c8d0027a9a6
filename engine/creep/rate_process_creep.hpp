#pragma once
// Time-dependent contact mechanism (docs/creep.md), applied between mechanical
// relaxations over a physical-time increment dt:
//
// 1. Rate-process viscous slip at frictional soil-soil contacts (Kuhn & Mitchell 1993):
//      v = A * sinh(beta * f) * max(0, 1 - s / s_lim) / (1 - D_c),   f = |Fs| / (mu Fn) in [0, 1]
//      s_lim = s_h * f / ((1 - f + 0.05) (1 - D_c))
//    with s the contact's accumulated creep slip and s_lim its delayed-slip capacity (a
//    Kelvin element in rate-process form: interlocking stops the slip, so creep decelerates
//    and converges; a higher load raises f and opens new capacity, near sliding the
//    capacity is large) and D_c the asperity damage of the contact, grown by
//    stress corrosion where the contact is close to sliding:
//      dD_c/dt = b1 * exp(b2 * f)   when f > f_th      (D_c capped at 0.95)
//    so that near failure (S ~ 0.8) damage outruns hardening late in the stage and the
//    rate rises again (tertiary creep); at low mobilisation D_c stays ~0.
//    The slip over dt, delta = v dt (capped at the elastic shear displacement |Fs|/ks),
//    relaxes the shear spring: Fs <- Fs (1 - ks delta / |Fs|). The energy ks-spring
//    energy released is booked as creep dissipation.
// 2. Stress corrosion of contact bonds (Potyondy 2007), same b1, b2, threshold:
//      dD/dt = b1 * exp(b2 * rho)   when rho > rho_th,   rho = max(tension/Tn, |Fs|/Ss)
//    D scales the bond strengths by (1 - D); a bond breaks (engine) once its load
//    exceeds the reduced strength, which lets damage run away at high stress (tertiary).
//
// The DEM cycles after each update (relaxation at fixed boundary stress) carry no
// physical time: the physical clock is advanced only by dt (quasi-static mapping).
#include <cstdint>
#include <unordered_map>

#include "engine/core/world.hpp"

namespace triax::creep {

struct RateProcessParams {
    double slip_rate_a_m_s = 0.0;
    double slip_beta = 6.0;
    double slip_hardening_length_m = 5.0e-6;
    double damage_rate_b1_per_s = 0.0;
    double damage_b2 = 12.0;
    double damage_threshold = 0.55;
    int soil_group = 0;
};

struct CreepUpdateSummary {
    double dissipated_j = 0.0;     // spring energy relaxed by viscous slip
    double max_slip_m = 0.0;       // largest slip of the increment
    double mean_damage = 0.0;      // over bonded contacts
    double mean_asperity_damage = 0.0;  // over sliding-prone frictional contacts
    long bonds_damaged = 0;        // contacts whose damage grew
};

class RateProcessCreep {
public:
    explicit RateProcessCreep(const RateProcessParams& p) : p_(p) {}

    // Updates shear forces and bond damage of `world`'s contacts over dt (s). Books the
    // dissipation in world.energy().creep.
    CreepUpdateSummary advance(World& world, double dt_s);

    // Accumulated creep slip of pair (i, j), 0 if none.
    double accumulated_slip(int i, int j) const;

private:
    static std::uint64_t key(int i, int j) {
        return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)) << 32) | static_cast<std::uint32_t>(j);
    }
    RateProcessParams p_;
    struct State {
        double slip = 0.0;    // m, accumulated creep slip
        double damage = 0.0;  // asperity damage D_c
    };
    std::unordered_map<std::uint64_t, State> state_;
};

}  // namespace triax::creep
