#pragma once
// The gather: each particle sums the forces and torques its contact slots hold, in a fixed
// order (its ball-ball slots in slot order, then its wall slots), so the sum is the same
// whichever thread computed the slots. No shared writes: a particle is gathered by one
// thread only.
//
// Also the particle's contact stiffness sums for density scaling (N/m: kn + ks per active
// contact; rotational N m: ks r^2), only when asked.
#include "engine/contact/contact_law.hpp"
#include "engine/contact/contact_store.hpp"
#include "engine/core/particle_arrays.hpp"

#include <vector>

namespace triax::step {

struct GatheredForce {
    Vec3 force = Vec3::Zero();   // N, contacts only
    Vec3 torque = Vec3::Zero();  // N m
    double stiffness = 0.0;      // N/m, sum of kn + ks (0 unless asked)
    double rot_stiffness = 0.0;  // N m, sum of ks r^2 (0 unless asked)
};

struct ForceGather {
    const ContactStore& contacts;
    const WallContactStore& wall_contacts;
    // Per-particle lists (CSR): ball-ball entries are slot*2 + side (0: the particle is i,
    // 1: it is j); wall entries are wall slots.
    const std::vector<int>& adj_start;
    const std::vector<int>& adj;
    const std::vector<int>& wall_adj_start;
    const std::vector<int>& wall_adj;
    const std::vector<ContactLaw>& laws;
    bool need_stiffness;

    [[gnu::always_inline]] inline GatheredForce operator()(long p, double radius) const {
        const ContactStore& c = contacts;
        const WallContactStore& wc = wall_contacts;
        // Branch-free: the side bit picks the sign of the force and the torque array.
        const double side_sign[2] = {-1.0, 1.0};
        const Vec3* const side_torque[2] = {c.torque_on_i.data(), c.torque_on_j.data()};
        Vec3 f = Vec3::Zero(), t = Vec3::Zero();
        double kt = 0.0, kr = 0.0;
        for (int e = adj_start[p]; e < adj_start[p + 1]; ++e) {
            const int slot = adj[e] >> 1, side = adj[e] & 1;
            // Every candidate slot is added: inactive ones hold zero force and torque
            // (contact_forces.hpp keeps that invariant, contact_store.hpp), and adding +0
            // leaves the sums' bits unchanged (a sum that starts at +0 is never -0, and
            // x + 0 = x). Whether a slot is active is random from slot to slot, so a branch
            // here (skipping the inactive ones) would be mispredicted often.
            f += side_sign[side] * c.force_on_j[slot];
            t += side_torque[side][slot];
            if (need_stiffness && c.active[slot]) {
                const ContactLaw& l = laws[c.law[slot]];
                kt += l.kn + l.ks;
                kr += l.ks * radius * radius;
            }
        }
        for (int e = wall_adj_start[p]; e < wall_adj_start[p + 1]; ++e) {
            const int slot = wall_adj[e];
            if (!wc.active[slot]) continue;  // zero force and torque, as above
            f += wc.force_on_particle[slot];
            t += wc.torque_on_particle[slot];
            if (need_stiffness) {
                const ContactLaw& l = laws[wc.law[slot]];
                kt += l.kn + l.ks;
                kr += l.ks * radius * radius;
            }
        }
        return {f, t, kt, kr};
    }
};

}  // namespace triax::step
