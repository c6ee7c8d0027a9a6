#pragma once
// The linear contact law with PFC semantics, as an evaluator struct: parameters in
// LinearContact::Params, physics in evaluate(). The loop (World) computes the pair
// kinematics and owns the history slots; the law only turns them into forces.
//
//   Fn = kn * overlap + Fd,   Fd = -2 beta sqrt(m_eff kn) v_n        (compression > 0)
//   Fs <- rotate(Fs) - ks * v_s dt,  |Fs| <= mu Fn  (Coulomb slider, unbonded only)
//   contact bond (if intact): tension allowed; breaks when -Fn_el >= sn (1 - damage)
//     (tension) or |Fs| >= ss (1 - damage) + mu_b max(Fn_el, 0) (shear; mu_b = bond
//     friction, 0 for PFC's contact bond; a bond friction above mu fades with the damage,
//     bond_shear_strength.hpp); then frictional.
//   rolling resistance (kRolling): M <- rotate(M) - kr dtheta_b,  kr = f ks Rbar^2,
//     |M| <= mu_r Rbar Fn.
//   cement neck of an intact bond (bond_rolling_friction mu_rb > 0, needs kRolling): while
//     bonded and uncracked, the rolling spring holds |M| < (mu_r + mu_rb (1 - damage)) Rbar
//     max(Fn_el, 0): the normal force may shift across the neck, of half-width mu_rb Rbar,
//     as across the flat of an angular contact (Iwashita & Oda), and corrosion narrows it,
//     as Potyondy's stress corrosion shrinks a parallel bond. At the limit the neck cracks
//     (neck_cracked): the bond keeps its cohesion, the contact keeps only mu_r; the
//     moment spring's energy is released as bond_break energy.
// kStateEnergy: whether to return the springs' stored energy (strain, bond_strain). It is
// a state function that the World books only on the last step of a cycle() call (the only
// one a caller can read); the dissipations (slip, dashpot, bond_break) are always booked.
// n points from the first body (i, or the wall) to the second (j, or the particle);
// all returned forces/moments act on the second body.
#include "engine/contact/bond_shear_strength.hpp"
#include "engine/contact/contact_law.hpp"
#include "engine/core/types.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace triax {

struct LinearContact {
    // The contact pass runs this law's plain frictional slots (unbonded, no dashpot, no
    // rolling resistance) four at a time (engine/core/step/frictional_lanes.hpp).
    static constexpr bool kRunsFrictionalLanes = true;

    struct Params {
        double kn, ks, friction, damping_ratio, rolling_friction, rolling_stiffness_factor, bond_friction,
            bond_rolling_friction;
        static Params from(const ContactLaw& l) {
            return {l.kn, l.ks, l.friction, l.normal_damping_ratio, l.rolling_friction,
                    l.rolling_stiffness_factor, l.bond_friction, l.bond_rolling_friction};
        }
    };

    // Kinematics of the pair at this step.
    struct Kinematics {
        Vec3 n;            // unit normal, first -> second body
        double overlap;    // m, effective (negative = gap)
        Vec3 v_rel;        // m/s, velocity of the second body's contact point relative to the first
        Vec3 w_rel;        // rad/s, spin of the second body minus the first
        double m_eff;      // kg
        double r_bar;      // m, effective radius for rolling resistance
        double dt;         // s
    };

    // History slots (references into a contact store).
    struct History {
        double& normal_force;
        Vec3& shear_force;
        Vec3& rolling_moment;
        std::uint8_t* bonded;        // nullptr for contacts that cannot be bonded (walls)
        std::uint8_t* neck_cracked;  // the bond's cement neck cracked (nullptr: walls)
        double bond_normal_strength;
        double bond_shear_strength;
        double damage;
    };

    // What happened this step (energies in J).
    struct Outcome {
        Vec3 force;                  // on the second body, N
        Vec3 moment;                 // rolling moment on the second body, N m
        double strain = 0.0, bond_strain = 0.0, slip = 0.0, dashpot = 0.0, bond_break = 0.0;
        bool active = false, broke_tension = false, broke_shear = false;
    };

    // sqrt(x2) compared with s exactly as std::sqrt(x2) >= s (or > s) compares, without the
    // sqrt when x2 is clearly below s^2: x2 < s^2 (1 - 2^-48) (s^2 rounded twice, < 1e-15
    // relative) puts sqrt(x2) at least 7 ulps below s, so the rounded sqrt is below s too.
    // Only near cases and s <= 0 take the sqrt. Most contacts stick and most bonds hold, so
    // the sqrt (long latency, on the force's critical path) is mostly skipped; the result,
    // and so the trajectory, is bitwise the one of the plain comparison.
    static constexpr double kClearlyBelow = 1.0 - 0x1p-48;
    static bool clearly_below(double x2, double s) {
        return s > 0.0 && x2 < s * s * kClearlyBelow;
    }
    static bool norm_at_least(double x2, double s) { return !clearly_below(x2, s) && std::sqrt(x2) >= s; }
    static bool norm_above(double x2, double s) { return !clearly_below(x2, s) && std::sqrt(x2) > s; }

    // PFC keeps the magnitude of a shear quantity when the contact plane turns: project
    // onto the new plane and rescale.
    static Vec3 rotate_into_plane(const Vec3& s, const Vec3& n) {
        const double mag2 = s.squaredNorm();
        if (mag2 == 0.0) return s;
        Vec3 t = s - n * n.dot(s);
        const double t2 = t.squaredNorm();
        if (t2 == 0.0) return Vec3::Zero();
        return t * std::sqrt(mag2 / t2);
    }

    template <bool kRolling, bool kStateEnergy = true>
    [[gnu::always_inline]] static inline Outcome evaluate(const Params& p, const Kinematics& k, History& h) {
        Outcome out;
        const bool was_bonded = h.bonded && *h.bonded;
        if (!was_bonded && k.overlap <= 0.0) {
            h.normal_force = 0.0;
            h.shear_force.setZero();
            h.rolling_moment.setZero();
            out.force.setZero();
            out.moment.setZero();
            return out;
        }
        out.active = true;
        const Vec3 fs_rot = rotate_into_plane(h.shear_force, k.n);
        const double vn = k.v_rel.dot(k.n);
        const Vec3 dus = (k.v_rel - k.n * vn) * k.dt;
        const double fn_el = p.kn * k.overlap;
        Vec3 fs = fs_rot - p.ks * dus;
        double fd = 0.0;
        if (p.damping_ratio > 0.0) {
            const double c = 2.0 * p.damping_ratio * std::sqrt(k.m_eff * p.kn);
            fd = -c * vn;
            out.dashpot = c * vn * vn * k.dt;
        }
        bool bonded = was_bonded;
        if (bonded) {
            const double keep = 1.0 - h.damage;
            if (-fn_el >= h.bond_normal_strength * keep) {
                bonded = false;
                out.broke_tension = true;
            } else if (norm_at_least(fs.squaredNorm(),
                                     bond_shear_strength(h.bond_shear_strength, p.bond_friction, p.friction, fn_el, h.damage))) {
                bonded = false;
                out.broke_shear = true;
            }
            if (!bonded) {
                *h.bonded = 0;
                if (k.overlap <= 0.0) {
                    // The bond held the only force: its spring energy is released.
                    out.bond_break = 0.5 * fn_el * fn_el / p.kn +
                                     (p.ks > 0 ? 0.5 * fs_rot.squaredNorm() / p.ks : 0.0);
                    if constexpr (kRolling) {
                        const double kr = p.rolling_stiffness_factor * p.ks * k.r_bar * k.r_bar;
                        if (kr > 0) out.bond_break += 0.5 * h.rolling_moment.squaredNorm() / kr;
                    }
                    h.normal_force = 0.0;
                    h.shear_force.setZero();
                    h.rolling_moment.setZero();
                    out.force.setZero();
                    out.moment.setZero();
                    out.active = false;
                    return out;
                }
            }
        }
        if (!bonded) {
            const double limit = p.friction * fn_el;
            const double fs2 = fs.squaredNorm();
            if (norm_above(fs2, limit)) {
                const double mag = std::sqrt(fs2);
                const Vec3 fs_new = mag > 0 ? Vec3(fs * (limit / mag)) : Vec3::Zero();
                // slip = work absorbed by the contact - change of the spring energy
                const double absorbed = -0.5 * (fs_rot + fs_new).dot(dus);
                const double d_spring = p.ks > 0 ? (fs_new.squaredNorm() - fs_rot.squaredNorm()) / (2.0 * p.ks) : 0.0;
                out.slip += absorbed - d_spring;
                fs = fs_new;
            }
        }
        double spring = 0.0;
        if constexpr (kStateEnergy) spring = 0.5 * fn_el * fn_el / p.kn + (p.ks > 0 ? 0.5 * fs.squaredNorm() / p.ks : 0.0);
        Vec3 moment = Vec3::Zero();
        if constexpr (kRolling) {
            const bool neck = bonded && p.bond_rolling_friction > 0.0 && h.neck_cracked && !*h.neck_cracked;
            const bool had_neck = was_bonded && p.bond_rolling_friction > 0.0 && h.neck_cracked && !*h.neck_cracked;
            const double kr = p.rolling_stiffness_factor * p.ks * k.r_bar * k.r_bar;
            if (p.rolling_friction > 0.0 || neck) {
                const Vec3 m_rot = rotate_into_plane(h.rolling_moment, k.n);
                const Vec3 dth = (k.w_rel - k.n * k.n.dot(k.w_rel)) * k.dt;
                moment = m_rot - kr * dth;
                if (neck) {
                    const double neck_limit =
                        bond_neck_moment_limit(p.rolling_friction, p.bond_rolling_friction, k.r_bar, fn_el, h.damage);
                    if (norm_at_least(moment.squaredNorm(), neck_limit)) {
                        *h.neck_cracked = 1;
                        if (kr > 0) out.bond_break += 0.5 * m_rot.squaredNorm() / kr;
                        moment = Vec3::Zero();  // the rolling slider carries on from the next step
                    }
                } else {
                    const double limit = p.rolling_friction * k.r_bar * std::max(fn_el, 0.0);
                    const double mag = moment.norm();
                    if (mag > limit) {
                        const Vec3 m_new = mag > 0 ? Vec3(moment * (limit / mag)) : Vec3::Zero();
                        const double absorbed = -0.5 * (m_rot + m_new).dot(dth);
                        const double d_spring = kr > 0 ? (m_new.squaredNorm() - m_rot.squaredNorm()) / (2.0 * kr) : 0.0;
                        out.slip += absorbed - d_spring;
                        moment = m_new;
                    }
                }
                if constexpr (kStateEnergy)
                    if (kr > 0) spring += 0.5 * moment.squaredNorm() / kr;
            } else if (had_neck && kr > 0) {
                // The bond broke in shear this step: its neck's moment spring is released.
                out.bond_break += 0.5 * h.rolling_moment.squaredNorm() / kr;
            }
        }
        if (bonded) out.bond_strain = spring;
        else out.strain = spring;
        h.normal_force = fn_el + fd;
        h.shear_force = fs;
        h.rolling_moment = moment;
        out.force = k.n * (fn_el + fd) + fs;
        out.moment = moment;
        return out;
    }
};

}  // namespace triax
