#pragma once
// Contact forces between spheres, written once as a loop over contact slots and templated
// on the contact law's evaluator (HOOMD's pair-loop + evaluator split): the law is inlined,
// with no virtual call or branch on the law per contact.
//
// The loop owns the geometry and the history slots: it computes the pair kinematics
// (normal n from i to j, overlap, relative velocity of j's contact point, spins, m_eff,
// R_bar), passes the slot's history to the evaluator, and stores the force on j and the
// torques on i and j in the slot. The gather (force_gather.hpp) adds them per particle.
// Invariant kept here: inactive slots hold zero force and torque.
//
// An Evaluator (LinearContact, engine/contact/linear.hpp) provides Params, Kinematics,
// History, Outcome and evaluate<kRolling, kStateEnergy>(params, kinematics, history).
// The linear law's plain frictional slots also have a four-lane kernel
// (frictional_lanes.hpp) that gives them the bits of the scalar path below.
#include "engine/contact/contact_store.hpp"
#include "engine/core/particle_arrays.hpp"
#include "engine/core/step/frictional_lanes.hpp"
#include "engine/core/step/step_blocks.hpp"
#include "engine/energy/step_sums.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <vector>

namespace triax::step {

// Whether slot k needs the law this step: bonded, or the spheres (after the reference
// gap and the creep offset) overlap. Written once, used by the screen and by the law's
// pass, so the decision and the d2 it is made on are the same expression in both.
struct PairGeometry {
    Vec3 d;          // m, x_j - x_i
    double d2;       // m^2, |d|^2
    double shift;    // m, reference gap - creep offset
    bool touching;   // needs the law (bonded or overlapping)
};
[[gnu::always_inline]] inline PairGeometry pair_geometry(const ContactStore& c, const ParticleArrays& pa, long k) {
    const int i = c.i[k], j = c.j[k];
    PairGeometry g;
    g.d = pa.position[j] - pa.position[i];
    const double ri = pa.radius[i], rj = pa.radius[j];
    g.shift = c.reference_gap[k] - c.plastic_overlap[k];
    const double reach = ri + rj + g.shift;
    g.d2 = g.d.squaredNorm();
    g.touching = c.bonded[k] || !(reach <= 0.0 || g.d2 >= reach * reach);
    return g;
}

template <class Evaluator>
struct ContactForces {
    using Params = typename Evaluator::Params;

    // One block of ball-ball slots [b kContactBlock, (b + 1) kContactBlock): forces into
    // the slots, energies into the block's sums. `rolling`: any law has rolling resistance
    // or a neck; `state_energy`: return the springs' stored energy (the call's last step).
    // Both are chosen once per block, outside the slot loop.
    static ContactSums block(ContactStore& c, const ParticleArrays& pa, const std::vector<Params>& params, double dt,
                             long b, bool rolling, bool state_energy) {
        if (state_energy)
            return rolling ? block<true, true>(c, pa, params, dt, b) : block<false, true>(c, pa, params, dt, b);
        return rolling ? block<true, false>(c, pa, params, dt, b) : block<false, false>(c, pa, params, dt, b);
    }

    // Two passes: a branch-free screen lists the slots that touch (or are bonded) and the
    // active ones that opened; the law then runs over the listed slots only, in slot order
    // (so the block's sums add up in slot order). Most candidate slots of a dense packing
    // do not touch, and whether one does is random from slot to slot, so a branch on it
    // inside the law's loop would be mispredicted often.
    template <bool kRolling, bool kStateEnergy>
    static ContactSums block(ContactStore& c, const ParticleArrays& pa, const std::vector<Params>& params, double dt,
                             long b) {
        const long ns = static_cast<long>(c.size());
        const long begin = b * kContactBlock, end = std::min(ns, (b + 1) * kContactBlock);
        int touching[kContactBlock], opened[kContactBlock];
        int n_touching = 0, n_opened = 0;
        for (long k = begin; k < end; ++k) {
            const bool touch = pair_geometry(c, pa, k).touching;
            const int local = static_cast<int>(k - begin);
            touching[n_touching] = local;
            n_touching += touch;
            opened[n_opened] = local;
            n_opened += !touch & (c.active[k] != 0);
        }
        for (int e = 0; e < n_opened; ++e) open_slot(c, pa, begin + opened[e]);
        ContactSums sums;
        int e = 0;
        if constexpr (!kRolling && uses_frictional_lanes()) {
            // Four touching slots at a time through the lanes when all four are plain
            // frictional contacts, else through the scalar path; either way the same bits,
            // and the outcomes are added in slot order.
            const int lane_end = simd::avx2_available() ? n_touching : 0;
            for (; e + kLaneCount <= lane_end; e += kLaneCount) {
                long k[kLaneCount];
                for (int l = 0; l < kLaneCount; ++l) k[l] = begin + touching[e + l];
                if (!frictional_lanes(c, pa, params.data(), dt, k, kStateEnergy, sums))
                    for (int l = 0; l < kLaneCount; ++l)
                        sums.add(touching_slot<kRolling, kStateEnergy>(c, pa, params, dt, k[l]));
            }
        }
        for (; e < n_touching; ++e)
            sums.add(touching_slot<kRolling, kStateEnergy>(c, pa, params, dt, begin + touching[e]));
        return sums;
    }

private:
    // The linear law runs its plain frictional slots through frictional_lanes.hpp unless the
    // evaluator says otherwise (kRunsFrictionalLanes = false: the scalar path only).
    static constexpr bool uses_frictional_lanes() {
        if constexpr (std::is_same_v<typename Evaluator::Params, LinearContact::Params> &&
                      requires { Evaluator::kRunsFrictionalLanes; })
            return Evaluator::kRunsFrictionalLanes;
        else
            return false;
    }

    // A slot that was active and no longer touches: history cleared, zero force. The
    // plastic overlap (crushing) survives while the spheres still overlap geometrically
    // (the contact was relaxed, not separated).
    [[gnu::always_inline]] static inline void open_slot(ContactStore& c, const ParticleArrays& pa, long k) {
        const int i = c.i[k], j = c.j[k];
        const double ri = pa.radius[i], rj = pa.radius[j];
        const double d2 = (pa.position[j] - pa.position[i]).squaredNorm();
        const double geo = ri + rj + c.reference_gap[k];
        const double keep_plastic = (geo > 0 && d2 < geo * geo) ? c.plastic_overlap[k] : 0.0;
        c.reset_history(k);
        c.plastic_overlap[k] = keep_plastic;
        c.force_on_j[k].setZero();
        c.torque_on_i[k].setZero();
        c.torque_on_j[k].setZero();
        c.overlap[k] = 0.0;
    }

    // A touching (or bonded) slot: kinematics at the contact point (PFC: the middle of the
    // geometric overlap), the law, and the slot's force and torques.
    template <bool kRolling, bool kStateEnergy>
    [[gnu::always_inline]] static inline typename Evaluator::Outcome touching_slot(
        ContactStore& c, const ParticleArrays& pa, const std::vector<Params>& params, double dt, long k) {
        const int i = c.i[k], j = c.j[k];
        const PairGeometry g = pair_geometry(c, pa, k);
        const double ri = pa.radius[i], rj = pa.radius[j];
        const double dist = std::sqrt(g.d2);
        const Vec3 n = g.d / dist;
        const double geo_overlap = ri + rj - dist;
        const Vec3 xc = pa.position[i] + n * (ri - 0.5 * geo_overlap);
        const Vec3 ai = xc - pa.position[i], aj = xc - pa.position[j];
        typename Evaluator::Kinematics kin;
        kin.n = n;
        kin.overlap = geo_overlap + g.shift;
        kin.v_rel = (pa.velocity[j] + pa.angular_velocity[j].cross(aj)) - (pa.velocity[i] + pa.angular_velocity[i].cross(ai));
        kin.w_rel = pa.angular_velocity[j] - pa.angular_velocity[i];
        kin.m_eff = pa.mass[i] * pa.mass[j] / (pa.mass[i] + pa.mass[j]);
        kin.r_bar = ri * rj / (ri + rj);
        kin.dt = dt;
        typename Evaluator::History h{c.normal_force[k], c.shear_force[k], c.rolling_moment[k], &c.bonded[k],
                                      &c.neck_cracked[k], c.bond_normal_strength[k], c.bond_shear_strength[k],
                                      c.damage[k]};
        const typename Evaluator::Outcome o =
            Evaluator::template evaluate<kRolling, kStateEnergy>(params[c.law[k]], kin, h);
        c.overlap[k] = kin.overlap;
        c.contact_point[k] = xc;
        if (!o.active) {
            c.reset_history(k);
            c.force_on_j[k].setZero();
            c.torque_on_i[k].setZero();
            c.torque_on_j[k].setZero();
            return o;
        }
        c.active[k] = 1;
        c.force_on_j[k] = o.force;
        c.torque_on_i[k] = ai.cross(-o.force) - o.moment;
        c.torque_on_j[k] = aj.cross(o.force) + o.moment;
        return o;
    }
};

}  // namespace triax::step
