#include "engine/integrate/sphere_lanes.hpp"

#include "engine/core/simd/lanes.hpp"

namespace triax {

using namespace simd;

namespace {

// sign_of (local_damping.hpp) per lane: exactly 1, -1 or +0 (also +0 for NaN).
TRIAX_LANES Lanes sign_lanes(Lanes v) {
    const Lanes zero = broadcast(0.0);
    const Mask one = (Mask)broadcast(1.0);
    return (Lanes)((v > zero) & one) - (Lanes)((v < zero) & one);
}
// local_damping_force per lane: F - (alpha |F|) sign(v), componentwise.
TRIAX_LANES Vec3Lanes local_damping_lanes(const Vec3Lanes& f, const Vec3Lanes& v, Lanes alpha) {
    return {f.x - alpha * abs_lanes(f.x) * sign_lanes(v.x), f.y - alpha * abs_lanes(f.y) * sign_lanes(v.y),
            f.z - alpha * abs_lanes(f.z) * sign_lanes(v.z)};
}

}  // namespace

[[gnu::target("avx2")]] bool integrate_sphere_lanes(const SphereIntegrator& in, long p, const Vec3* f_contact,
                                                    const Vec3* t_contact, const double* kt, const double* kr,
                                                    ParticleArrays& pa, std::vector<double>& inertial_mass,
                                                    std::vector<double>& inertial_inertia, BodySums& s) {
    if (pa.flags[p] | pa.flags[p + 1] | pa.flags[p + 2] | pa.flags[p + 3]) return false;
    const Lanes dt = broadcast(in.dt), half = broadcast(0.5);
    const Vec3Lanes g = broadcast(in.gravity);
    const Lanes mass = load(&pa.mass[p]);
    const Vec3Lanes ext = load(&pa.external_force[p]);
    const Vec3Lanes f = load(f_contact) + (ext + mass * g);
    const Vec3Lanes t = load(t_contact);
    store(f, &pa.force[p]);
    store(t, &pa.torque[p]);
    Lanes m = mass, inertia = load(&pa.inertia[p]);
    if (in.density_scaling) {
        m = max_lanes(m, broadcast(4.0) * load(kt) * dt * dt);
        inertia = max_lanes(inertia, broadcast(4.0) * load(kr) * dt * dt);
    }
    store(m, &inertial_mass[p]);
    store(inertia, &inertial_inertia[p]);
    const Vec3Lanes v_old = load(&pa.velocity[p]), w_old = load(&pa.angular_velocity[p]);
    const Lanes alpha = broadcast(in.alpha);
    const Vec3Lanes fd = local_damping_lanes(f, v_old, alpha);
    const Vec3Lanes td = local_damping_lanes(t, w_old, alpha);
    const Vec3Lanes v_new = v_old + fd * (dt / m);
    const Vec3Lanes w_new = w_old + td * (dt / inertia);
    const Vec3Lanes v_mid = half * (v_old + v_new), w_mid = half * (w_old + w_new);
    const Lanes damping = (dot(f - fd, v_mid) + dot(t - td, w_mid)) * dt;
    const Lanes boundary = dot(ext, v_mid) * dt;
    const Lanes body = mass * dot(g, v_mid) * dt;
    const Lanes v2 = dot(v_new, v_new), w2 = dot(w_new, w_new);
    const Lanes kinetic = half * m * v2 + half * inertia * w2;
    store(v_new, &pa.velocity[p]);
    store(w_new, &pa.angular_velocity[p]);
    store(load(&pa.position[p]) + v_new * dt, &pa.position[p]);
    // The block's sums in particle order, as four scalar calls would leave them.
    for (int l = 0; l < kLaneCount; ++l) {
        s.damping += damping[l];
        s.boundary += boundary[l];
        s.body += body[l];
        if (in.kinetic) s.kinetic += kinetic[l];
    }
    // The checks: SphereIntegrator::check_step_length's screen across the lanes; where a lane
    // fails it, or a domain box is set, the scalar checks run particle by particle.
    const Lanes r = load(&pa.radius[p]);
    const Mask stable = (v2 * (dt * dt) < r * r * SphereIntegrator::kStableBelow) & (w2 - w2 == broadcast(0.0));
    if (in.has_domain || any(~stable)) {
        for (int l = 0; l < kLaneCount; ++l) {
            const long q = p + l;
            in.check_step_length(q, lane(v_new, l), lane(w_new, l), pa.radius[q], s);
            in.check_domain(q, pa, s);
        }
    }
    return true;
}

}  // namespace triax
