#include "engine/core/step/frictional_lanes.hpp"

#include "engine/core/simd/lanes.hpp"

namespace triax::step {

using namespace simd;

[[gnu::target("avx2")]] bool frictional_lanes(ContactStore& c, const ParticleArrays& pa,
                                              const LinearContact::Params* params, double dt, const long* k,
                                              bool state_energy, ContactSums& sums) {
    int i[kLaneCount], j[kLaneCount];
    Lanes ri, rj, shift, kn, ks, mu;
    for (int l = 0; l < kLaneCount; ++l) {
        const LinearContact::Params& p = params[c.law[k[l]]];
        if (c.bonded[k[l]] || p.damping_ratio > 0.0) return false;
        i[l] = c.i[k[l]];
        j[l] = c.j[k[l]];
        ri[l] = pa.radius[i[l]];
        rj[l] = pa.radius[j[l]];
        shift[l] = c.reference_gap[k[l]] - c.plastic_overlap[k[l]];
        kn[l] = p.kn;
        ks[l] = p.ks;
        mu[l] = p.friction;
    }
    const Lanes zero = broadcast(0.0);
    const Vec3Lanes zero3{zero, zero, zero};
    // Kinematics at the contact point, the middle of the geometric overlap (touching_slot).
    const Vec3Lanes xi = gather(pa.position, i), xj = gather(pa.position, j);
    const Vec3Lanes d = xj - xi;
    const Lanes dist = sqrt_lanes(dot(d, d));
    const Vec3Lanes n{d.x / dist, d.y / dist, d.z / dist};
    const Lanes geo_overlap = ri + rj - dist;
    const Lanes overlap = geo_overlap + shift;
    if (any(~(overlap > zero))) return false;  // a law without contact: the scalar path resets it
    const Vec3Lanes xc = xi + n * (ri - 0.5 * geo_overlap);
    const Vec3Lanes ai = xc - xi, aj = xc - xj;
    const Vec3Lanes v_rel = (gather(pa.velocity, j) + cross(gather(pa.angular_velocity, j), aj)) -
                            (gather(pa.velocity, i) + cross(gather(pa.angular_velocity, i), ai));
    // The shear history turned into the new plane with its magnitude kept
    // (LinearContact::rotate_into_plane): s itself when zero, zero when along n.
    const Vec3Lanes s = gather(c.shear_force, k);
    const Lanes mag2 = dot(s, s);
    const Vec3Lanes t = s - n * dot(n, s);
    const Lanes t2 = dot(t, t);
    const Vec3Lanes fs_rot = select(mag2 == zero, s, select(t2 == zero, zero3, t * sqrt_lanes(mag2 / t2)));
    // The law (LinearContact::evaluate, unbonded, no dashpot).
    const Lanes vn = dot(v_rel, n);
    const Vec3Lanes dus = (v_rel - n * vn) * broadcast(dt);
    const Lanes fn_el = kn * overlap;
    Vec3Lanes fs = fs_rot - dus * ks;
    const Lanes limit = mu * fn_el;
    const Lanes fs2 = dot(fs, fs);
    // LinearContact::norm_above(fs2, limit), lane by lane: the sqrt only when some lane is
    // not clearly below the limit.
    const Mask clearly_below = (limit > zero) & (fs2 < limit * limit * LinearContact::kClearlyBelow);
    Lanes slip = zero;
    bool slipped = false;
    if (any(~clearly_below)) {
        const Lanes mag = sqrt_lanes(fs2);
        const Mask slides = ~clearly_below & (mag > limit);
        if (any(slides)) {
            slipped = true;
            const Vec3Lanes fs_new = select(mag > zero, fs * (limit / mag), zero3);
            const Lanes absorbed = -0.5 * dot(fs_rot + fs_new, dus);
            const Lanes d_spring = ks > zero ? (dot(fs_new, fs_new) - dot(fs_rot, fs_rot)) / (2.0 * ks) : zero;
            slip = slides ? zero + (absorbed - d_spring) : zero;
            fs = select(slides, fs_new, fs);
        }
    }
    // The springs' stored energy (evaluate's kStateEnergy), on the steps that book it.
    Lanes strain = zero;
    if (state_energy) {
        const Lanes fs2_kept = dot(fs, fs);
        strain = 0.5 * fn_el * fn_el / kn + (ks > zero ? 0.5 * fs2_kept / ks : zero);
    }
    const Lanes fn = fn_el + zero;  // fn_el + the absent dashpot's 0
    const Vec3Lanes force = n * fn + fs;
    const Vec3Lanes torque_i = cross(ai, -force) - zero3;  // minus the absent moment
    const Vec3Lanes torque_j = cross(aj, force) + zero3;
    for (int l = 0; l < kLaneCount; ++l) {
        const long kk = k[l];
        c.normal_force[kk] = fn[l];
        c.shear_force[kk] = lane(fs, l);
        c.rolling_moment[kk].setZero();
        c.overlap[kk] = overlap[l];
        c.contact_point[kk] = lane(xc, l);
        c.active[kk] = 1;
        c.force_on_j[kk] = lane(force, l);
        c.torque_on_i[kk] = lane(torque_i, l);
        c.torque_on_j[kk] = lane(torque_j, l);
    }
    // The outcomes' energies added in slot order, as ContactSums::add would add them. Only
    // the strain (on the steps that book it) and the slip can be non-zero; the terms left
    // out are +0, and adding +0 to a sum that started at +0 changes no bit.
    for (int l = 0; l < kLaneCount; ++l) {
        if (state_energy) sums.strain += strain[l];
        if (slipped) sums.slip += slip[l];
    }
    return true;
}

}  // namespace triax::step
