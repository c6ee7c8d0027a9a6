// World::cycle: the time step. Forces go into per-contact slots (parallel over
// contacts, no shared writes), then each particle gathers its slots in a fixed order
// (parallel over particles). Reductions go through fixed-size blocks summed serially,
// so results do not depend on the thread count. With 2+ threads a run of steps shares
// one OpenMP region and meets at three barriers per step, not two regions per step.
#include "engine/contact/linear.hpp"
#include "engine/core/world.hpp"
#include "engine/integrate/local_damping.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <sstream>

namespace triax {

namespace {

// Reduction blocks: partial sums per block, summed serially in block order, so results
// do not depend on the thread count or on which thread ran a block. Blocks are handed
// out dynamically: the work per item is uneven (a specimen's grains come first and have
// more contacts than its membrane spheres; far candidate slots cost almost nothing), and
// static halves left one of two threads idle for up to half of the step.
constexpr int kBlock = 1024;          // contact slots
constexpr int kParticleBlock = 256;   // particles (gather + integration)
// Below this many items a parallel region costs more than it saves (thread wake-up);
// the block structure is the same either way, so results do not change.
constexpr long kParallelMin = 4096;

struct ContactSums {
    double strain = 0, bond_strain = 0, slip = 0, dashpot = 0, bond_break = 0;
    long broke_tension = 0, broke_shear = 0;
    void add(const LinearContact::Outcome& o) {
        strain += o.strain; bond_strain += o.bond_strain; slip += o.slip;
        dashpot += o.dashpot; bond_break += o.bond_break;
        broke_tension += o.broke_tension; broke_shear += o.broke_shear;
    }
    void add(const ContactSums& o) {
        strain += o.strain; bond_strain += o.bond_strain; slip += o.slip;
        dashpot += o.dashpot; bond_break += o.bond_break;
        broke_tension += o.broke_tension; broke_shear += o.broke_shear;
    }
};

// Blocks [0, n) handed out from both ends: thread 0 takes them from the front, the other
// threads from the back. Contact slots are sorted by their first particle and particle
// blocks follow the particle index, so a thread tends to gather the forces that it wrote
// itself and to integrate the particles whose contacts it computed (fewer cache lines
// moving between the cores than with one counter, where the blocks' owners are random),
// and the split point still follows the load (dynamic). Which thread runs a block does not
// change the results (partial sums per block, reduced in block order).
class TwoEndedBlocks {
public:
    void reset(long n) { ends_.store(static_cast<std::uint64_t>(n), std::memory_order_relaxed); }
    // The next block for thread `tid`, or -1 when none is left.
    long take(int tid) {
        std::uint64_t e = ends_.load(std::memory_order_relaxed);
        while (true) {
            const std::uint64_t front = e >> 32, back = e & 0xffffffffu;
            if (front >= back) return -1;
            const std::uint64_t next = tid == 0 ? ((front + 1) << 32) | back : (front << 32) | (back - 1);
            if (ends_.compare_exchange_weak(e, next, std::memory_order_relaxed))
                return static_cast<long>(tid == 0 ? front : back - 1);
        }
    }

private:
    std::atomic<std::uint64_t> ends_{0};  // front in the high 32 bits, back (exclusive) in the low
};

struct ParticleSums {
    double kinetic = 0, damping = 0, boundary = 0, body = 0, max_disp2 = 0;
    long bad = -1;  // first particle index that failed a stability check
    int cause = 0;
};

// Whether slot k needs the law this step: bonded, or the spheres (after the reference
// gap and the creep offset) overlap. Written once, used by the screen and by the law's
// pass, so the decision and the d2 it is made on are the same expression in both.
struct PairGeometry {
    Vec3 d;          // x_j - x_i
    double d2;       // |d|^2
    double shift;    // reference gap - creep offset
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

// One block of ball-ball slots: forces into the slots, energies into the block's sums
// (the springs' stored energy only when kStateEnergy: see StepState::state_energy).
// Two passes: a branch-free screen lists the slots that touch (or are bonded) and the
// active ones that opened; the law then runs over the listed slots only, in slot order
// (so the block's sums add up in the same order). Most candidate slots of a dense
// packing do not touch, and whether one does is random from slot to slot: as a branch
// inside the law's loop it was mispredicted often.
template <bool kRolling, bool kStateEnergy>
ContactSums ball_block(ContactStore& c, const ParticleArrays& pa, const std::vector<LinearContact::Params>& params,
                       double dt, long b) {
    const long ns = static_cast<long>(c.size());
    const long begin = b * kBlock, end = std::min(ns, (b + 1) * kBlock);
    int touching[kBlock], opened[kBlock];
    int n_touching = 0, n_opened = 0;
    for (long k = begin; k < end; ++k) {
        const bool touch = pair_geometry(c, pa, k).touching;
        const int local = static_cast<int>(k - begin);
        touching[n_touching] = local;
        n_touching += touch;
        opened[n_opened] = local;
        n_opened += !touch & (c.active[k] != 0);
    }
    for (int e = 0; e < n_opened; ++e) {
        const long k = begin + opened[e];
        const int i = c.i[k], j = c.j[k];
        const double ri = pa.radius[i], rj = pa.radius[j];
        const double d2 = (pa.position[j] - pa.position[i]).squaredNorm();
        // Opened. The plastic overlap (crushing) survives while the spheres still overlap
        // geometrically (the contact was relaxed, not separated).
        const double geo = ri + rj + c.reference_gap[k];
        const double keep_plastic = (geo > 0 && d2 < geo * geo) ? c.plastic_overlap[k] : 0.0;
        c.reset_history(k);
        c.plastic_overlap[k] = keep_plastic;
        c.force_on_j[k].setZero();
        c.torque_on_i[k].setZero();
        c.torque_on_j[k].setZero();
        c.overlap[k] = 0.0;
        // Invariant: inactive slots hold zero force and torque (the gather adds them).
    }
    ContactSums sums;
    for (int e = 0; e < n_touching; ++e) {
        const long k = begin + touching[e];
        const int i = c.i[k], j = c.j[k];
        const PairGeometry g = pair_geometry(c, pa, k);
        const Vec3 d = g.d;
        const double ri = pa.radius[i], rj = pa.radius[j];
        const double shift = g.shift;
        const double d2 = g.d2;
        const double dist = std::sqrt(d2);
        const Vec3 n = d / dist;
        const double geo_overlap = ri + rj - dist;
        const Vec3 xc = pa.position[i] + n * (ri - 0.5 * geo_overlap);
        const Vec3 ai = xc - pa.position[i], aj = xc - pa.position[j];
        LinearContact::Kinematics kin;
        kin.n = n;
        kin.overlap = geo_overlap + shift;
        kin.v_rel = (pa.velocity[j] + pa.angular_velocity[j].cross(aj)) - (pa.velocity[i] + pa.angular_velocity[i].cross(ai));
        kin.w_rel = pa.angular_velocity[j] - pa.angular_velocity[i];
        kin.m_eff = pa.mass[i] * pa.mass[j] / (pa.mass[i] + pa.mass[j]);
        kin.r_bar = ri * rj / (ri + rj);
        kin.dt = dt;
        LinearContact::History h{c.normal_force[k], c.shear_force[k], c.rolling_moment[k], &c.bonded[k], &c.neck_cracked[k],
                                 c.bond_normal_strength[k], c.bond_shear_strength[k], c.damage[k]};
        const LinearContact::Outcome o = LinearContact::evaluate<kRolling, kStateEnergy>(params[c.law[k]], kin, h);
        sums.add(o);
        c.overlap[k] = kin.overlap;
        c.contact_point[k] = xc;
        if (!o.active) {
            c.reset_history(k);
            c.force_on_j[k].setZero();
            c.torque_on_i[k].setZero();
            c.torque_on_j[k].setZero();
            continue;
        }
        c.active[k] = 1;
        c.force_on_j[k] = o.force;
        c.torque_on_i[k] = ai.cross(-o.force) - o.moment;
        c.torque_on_j[k] = aj.cross(o.force) + o.moment;
    }
    return sums;
}

}  // namespace

// Scratch of one cycle() call: the laws' evaluator parameters (laws do not change during
// a call) and the per-block partial sums of the current step.
struct World::StepState {
    std::vector<LinearContact::Params> params;
    // State energies (strain, bond strain, kinetic) are functions of the state: a caller
    // can only read the ledger between cycle() calls, so they are computed on the last
    // step of a call (the same code as on every step before, so the same numbers) and
    // skipped on the others (two divisions per contact). Kinetic energy is also needed on
    // every step when a kinetic-energy limit is set (check_stability).
    bool state_energy = true, kinetic = true;
    std::vector<ContactSums> contact_blocks;
    std::vector<ParticleSums> particle_blocks;
    ContactSums wall_sums;
    long contact_block_count = 0, particle_block_count = 0;
};

void World::prepare_step(StepState& st, bool last_step) {
    st.state_energy = last_step;
    st.kinetic = last_step || max_kinetic_ < std::numeric_limits<double>::infinity();
    st.contact_block_count = (static_cast<long>(contacts_.size()) + kBlock - 1) / kBlock;
    st.contact_blocks.assign(st.contact_block_count, ContactSums{});
    const long n = static_cast<long>(particles_.size());
    st.particle_block_count = (n + kParticleBlock - 1) / kParticleBlock;
    st.particle_blocks.assign(st.particle_block_count, ParticleSums{});
    st.wall_sums = ContactSums{};
}

void World::contact_block(StepState& st, long b) {
    if (st.state_energy)
        st.contact_blocks[b] = any_rolling_ ? ball_block<true, true>(contacts_, particles_, st.params, dt_, b)
                                            : ball_block<false, true>(contacts_, particles_, st.params, dt_, b);
    else
        st.contact_blocks[b] = any_rolling_ ? ball_block<true, false>(contacts_, particles_, st.params, dt_, b)
                                            : ball_block<false, false>(contacts_, particles_, st.params, dt_, b);
}

// Wall contacts: few, done in slot order by one thread (also gives the wall forces).
// Touches only wall slots, walls and reads particles: may run beside the ball blocks.
void World::wall_contacts_pass(StepState& st) {
    const std::vector<LinearContact::Params>& params = st.params;
    ContactSums& total = st.wall_sums;
    for (auto& w : plane_walls_) { w.force.setZero(); w.contact_count = 0; }
    for (auto& w : cylinder_walls_) { w.force.setZero(); w.radial_force = 0.0; w.contact_count = 0; }
    WallContactStore& wc = wall_contacts_;
    for (std::size_t k = 0; k < wc.size(); ++k) {
        const int p = wc.particle[k];
        const Vec3& x = particles_.position[p];
        const double r = particles_.radius[p];
        Vec3 n;           // wall -> particle
        double dist;      // centre to wall surface
        Vec3 v_wall;
        bool in_range = true;
        if (wc.wall_kind[k] == 0) {
            const PlaneWall& w = plane_walls_[wc.wall[k]];
            n = w.normal;
            dist = (x - w.point).dot(n);
            v_wall = w.velocity;
        } else {
            const CylinderWall& w = cylinder_walls_[wc.wall[k]];
            const Vec3 rel = x - w.base;
            const double a = rel.dot(w.axis);
            const Vec3 radial = rel - a * w.axis;
            const double rho = radial.norm();
            in_range = a >= 0.0 && a <= w.height && rho > 0.0;
            const Vec3 e = rho > 0 ? Vec3(radial / rho) : Vec3::UnitX();
            n = -e;
            dist = w.radius - rho;
            v_wall = w.velocity + w.radial_velocity * e;
        }
        const double overlap = r - dist;
        wc.overlap[k] = overlap;
        if (!in_range || overlap <= 0.0) {
            if (wc.active[k]) {
                wc.reset_history(k);
            }
            wc.force_on_particle[k].setZero();
            wc.torque_on_particle[k].setZero();
            continue;
        }
        // PFC places the contact point in the middle of the overlap.
        const Vec3 xc = x - n * (dist + 0.5 * (r - dist));
        const Vec3 arm = xc - x;
        LinearContact::Kinematics kin;
        kin.n = n;
        kin.overlap = overlap;
        kin.v_rel = particles_.velocity[p] + particles_.angular_velocity[p].cross(arm) - v_wall;
        kin.w_rel = particles_.angular_velocity[p];
        kin.m_eff = particles_.mass[p];
        kin.r_bar = r;
        kin.dt = dt_;
        Vec3 no_moment = Vec3::Zero();
        LinearContact::History h{wc.normal_force[k], wc.shear_force[k], no_moment, nullptr, nullptr, 0.0, 0.0, 0.0};
        // Few wall contacts: their stored energy is computed on every step (the same code).
        const LinearContact::Outcome o = any_rolling_
            ? LinearContact::evaluate<true>(params[wc.law[k]], kin, h)
            : LinearContact::evaluate<false>(params[wc.law[k]], kin, h);
        total.add(o);
        wc.active[k] = 1;
        wc.contact_point[k] = xc;
        wc.force_on_particle[k] = o.force;
        wc.torque_on_particle[k] = arm.cross(o.force) + o.moment;
        if (wc.wall_kind[k] == 0) {
            PlaneWall& w = plane_walls_[wc.wall[k]];
            w.force -= o.force;
            ++w.contact_count;
        } else {
            CylinderWall& w = cylinder_walls_[wc.wall[k]];
            w.force -= o.force;
            w.radial_force += wc.normal_force[k];
            ++w.contact_count;
        }
    }
}

void World::finish_contact_forces(StepState& st) {
    ContactSums total;
    for (const ContactSums& b : st.contact_blocks) total.add(b);
    total.add(st.wall_sums);
    broken_tension_ += total.broke_tension;
    broken_shear_ += total.broke_shear;
    if (track_energy_) {
        if (st.state_energy) {
            energy_.strain = total.strain;
            energy_.bond_strain = total.bond_strain;
        }
        energy_.slip += total.slip;
        energy_.dashpot += total.dashpot;
        energy_.bond_break += total.bond_break;
    }
}

void World::particle_block(StepState& st, long b) {
    const long n = static_cast<long>(particles_.size());
    ParticleArrays& pa = particles_;
    const ContactStore& c = contacts_;
    const WallContactStore& wc = wall_contacts_;
    const double dt = dt_;
    const double alpha = alpha_;
    const Vec3 g = gravity_;
    const bool scaling = density_scaling_;
    const bool need_stiffness = scaling;
    const bool kinetic = st.kinetic;
    const double dt2 = dt * dt;
    constexpr double kStableBelow = 1.0 - 0x1p-40;
    const auto& laws = resolved_laws_;
    const bool has_domain = domain_.has_value();
    const Vec3 lo = has_domain ? domain_->first : Vec3::Zero();
    const Vec3 hi = has_domain ? domain_->second : Vec3::Zero();

    const double side_sign[2] = {-1.0, 1.0};
    const Vec3* const side_torque[2] = {c.torque_on_i.data(), c.torque_on_j.data()};

    {
        ParticleSums s;
        const long end = std::min(n, (b + 1) * kParticleBlock);
        for (long p = b * kParticleBlock; p < end; ++p) {
            Vec3 f = Vec3::Zero(), t = Vec3::Zero();
            double kt = 0.0, kr = 0.0;
            for (int e = adj_start_[p]; e < adj_start_[p + 1]; ++e) {
                // Branch-free: the side bit picks the sign of the force and the torque array.
                const int slot = adj_[e] >> 1, side = adj_[e] & 1;
                // Every candidate slot is added: inactive ones hold zero force and torque
                // (ball_block keeps that invariant, contact_store.hpp), and adding +0 leaves
                // the sums' bits unchanged (a sum that starts at +0 is never -0, and
                // x + 0 = x). Whether a slot is active is random from slot to slot: as a
                // branch here (skipping the inactive ones) it was mispredicted often.
                f += side_sign[side] * c.force_on_j[slot];
                t += side_torque[side][slot];
                if (need_stiffness && c.active[slot]) {
                    const ContactLaw& l = laws[c.law[slot]];
                    kt += l.kn + l.ks;
                    kr += l.ks * pa.radius[p] * pa.radius[p];
                }
            }
            for (int e = wall_adj_start_[p]; e < wall_adj_start_[p + 1]; ++e) {
                const int slot = wall_adj_[e];
                if (!wc.active[slot]) continue;  // zero force and torque, as above
                f += wc.force_on_particle[slot];
                t += wc.torque_on_particle[slot];
                if (need_stiffness) {
                    const ContactLaw& l = laws[wc.law[slot]];
                    kt += l.kn + l.ks;
                    kr += l.ks * pa.radius[p] * pa.radius[p];
                }
            }
            stiffness_sum_[p] = kt;
            rot_stiffness_sum_[p] = kr;
            const Vec3 f_contact = f;
            f += pa.external_force[p] + pa.mass[p] * g;
            pa.force[p] = f;
            pa.torque[p] = t;
            const std::uint8_t flags = pa.flags[p];
            if (flags & kClumpMember) continue;
            if (flags & kFixedVelocity) {
                // Prescribed motion: what its contacts push against is boundary work.
                s.boundary += -f_contact.dot(pa.velocity[p]) * dt - t.dot(pa.angular_velocity[p]) * dt;
                pa.position[p] += pa.velocity[p] * dt;
            } else {
                double m = pa.mass[p], inertia = pa.inertia[p];
                if (scaling) {
                    m = std::max(m, 4.0 * kt * dt * dt);
                    inertia = std::max(inertia, 4.0 * kr * dt * dt);
                }
                inertial_mass_[p] = m;
                inertial_inertia_[p] = inertia;
                const Vec3 v_old = pa.velocity[p], w_old = pa.angular_velocity[p];
                const Vec3 fd = local_damping_force(f, v_old, alpha);
                const Vec3 td = local_damping_force(t, w_old, alpha);
                const Vec3 v_new = v_old + fd * (dt / m);
                const Vec3 w_new = w_old + td * (dt / inertia);
                const Vec3 v_mid = 0.5 * (v_old + v_new), w_mid = 0.5 * (w_old + w_new);
                s.damping += ((f - fd).dot(v_mid) + (t - td).dot(w_mid)) * dt;
                s.boundary += pa.external_force[p].dot(v_mid) * dt;
                s.body += pa.mass[p] * g.dot(v_mid) * dt;
                if (kinetic) s.kinetic += 0.5 * m * v_new.squaredNorm() + 0.5 * inertia * w_new.squaredNorm();
                pa.velocity[p] = v_new;
                pa.angular_velocity[p] = w_new;
                pa.position[p] += v_new * dt;
                // Stability check without a sqrt per particle: |v| dt is far below the radius
                // when |v|^2 dt^2 < r^2 (1 - 2^-40) (rounding: < 1e-15 relative), and then the
                // check below cannot fire; non-finite values fail the screen and are checked.
                const double v2 = v_new.squaredNorm(), r = pa.radius[p];
                if (s.bad < 0 && !(v2 * dt2 < r * r * kStableBelow && std::isfinite(w_new.squaredNorm()))) {
                    const double step_len = std::sqrt(v2) * dt;
                    if (!std::isfinite(step_len) || !std::isfinite(w_new.squaredNorm())) { s.bad = p; s.cause = 1; }
                    else if (step_len > r) { s.bad = p; s.cause = 2; }
                }
            }
            if (has_domain && s.bad < 0 &&
                ((pa.position[p].array() < lo.array()).any() || (pa.position[p].array() > hi.array()).any())) {
                s.bad = p; s.cause = 3;
            }
            s.max_disp2 = std::max(s.max_disp2, (pa.position[p] - rebuild_position_[p]).squaredNorm());
        }
        st.particle_blocks[b] = s;
    }
}

void World::finish_particles(StepState& st) {
    ParticleArrays& pa = particles_;
    const double dt = dt_;
    ParticleSums total;
    for (const ParticleSums& s : st.particle_blocks) {
        total.kinetic += s.kinetic; total.damping += s.damping; total.boundary += s.boundary; total.body += s.body;
        total.max_disp2 = std::max(total.max_disp2, s.max_disp2);
        if (total.bad < 0 && s.bad >= 0) { total.bad = s.bad; total.cause = s.cause; }
    }
    if (track_energy_) {
        if (st.kinetic) energy_.kinetic = total.kinetic;
        energy_.damping += total.damping;
        energy_.boundary_work += total.boundary;
        energy_.body_force_work += total.body;
    }
    if (total.bad >= 0) {
        const long p = total.bad;
        std::ostringstream why;
        if (total.cause == 1) why << "non-finite velocity (NaN) of particle " << p;
        else if (total.cause == 2)
            why << "exploding kinetic energy: particle " << p << " moved " << pa.velocity[p].norm() * dt
                << " m in one step, more than its radius " << pa.radius[p] << " m (time step too large or overlap too deep)";
        else
            why << "particle " << p << " escaped the domain box at (" << pa.position[p].x() << ", "
                << pa.position[p].y() << ", " << pa.position[p].z() << ") m";
        throw SimulationError(step_, why.str());
    }
    const double half_skin = 0.5 * skin();
    if (total.max_disp2 > half_skin * half_skin) need_rebuild_ = true;
}

void World::integrate_clumps(bool kinetic) {
    const double dt = dt_;
    for (Clump& c : clumps_) {
        Vec3 f = Vec3::Zero(), t = Vec3::Zero(), f_ext = Vec3::Zero(), f_contact = Vec3::Zero(), t_contact = Vec3::Zero();
        double kt = 0.0, kr = 0.0;
        for (int p : c.members) {
            const Vec3 arm = particles_.position[p] - c.position;
            f += particles_.force[p];
            t += arm.cross(particles_.force[p]) + particles_.torque[p];
            const Vec3 fc = particles_.force[p] - particles_.external_force[p] - particles_.mass[p] * gravity_;
            f_contact += fc;
            t_contact += arm.cross(fc) + particles_.torque[p];
            f_ext += particles_.external_force[p];
            kt += stiffness_sum_[p];
            kr += rot_stiffness_sum_[p] + stiffness_sum_[p] * arm.squaredNorm();
        }
        c.contact_force = f_contact;
        c.contact_torque = t_contact;
        if (c.control == ClumpControl::VelocityControlled) {
            if (track_energy_) energy_.boundary_work += -(f_contact.dot(c.velocity) + t_contact.dot(c.angular_velocity)) * dt;
        } else {
            f += c.applied_force;
            t += c.applied_torque;
            double m = c.mass;
            const Mat3 rot = c.orientation.toRotationMatrix();
            Mat3 inertia = rot * c.inertia_body * rot.transpose();
            if (density_scaling_) {
                m = std::max(m, 4.0 * kt * dt * dt);
                const double i_min = 4.0 * kr * dt * dt;
                for (int a = 0; a < 3; ++a) inertia(a, a) = std::max(inertia(a, a), i_min);
            }
            const Vec3 v_old = c.velocity, w_old = c.angular_velocity;
            const Vec3 fd = local_damping_force(f, v_old, alpha_);
            const Vec3 v_new = v_old + fd * (dt / m);
            Vec3 w_new = Vec3::Zero();
            Vec3 td = Vec3::Zero();
            if (!c.fix_rotation) {
                td = local_damping_force(t, w_old, alpha_);
                w_new = w_old + inertia.ldlt().solve(td) * dt;
            }
            const Vec3 v_mid = 0.5 * (v_old + v_new), w_mid = 0.5 * (w_old + w_new);
            if (track_energy_) {
                energy_.damping += (f - fd).dot(v_mid) * dt + (c.fix_rotation ? 0.0 : (t - td).dot(w_mid) * dt);
                energy_.boundary_work += (c.applied_force + f_ext).dot(v_mid) * dt + c.applied_torque.dot(w_mid) * dt;
                energy_.body_force_work += c.mass * gravity_.dot(v_mid) * dt;
                if (kinetic) energy_.kinetic += 0.5 * m * v_new.squaredNorm() + 0.5 * w_new.dot(inertia * w_new);
            }
            c.velocity = v_new;
            c.angular_velocity = w_new;
        }
        c.position += c.velocity * dt;
        const double w = c.angular_velocity.norm();
        if (w > 0) {
            const Eigen::Quaterniond dq(Eigen::AngleAxisd(w * dt, c.angular_velocity / w));
            c.orientation = (dq * c.orientation).normalized();
        }
        update_clump_members(c);
        const double half_skin = 0.5 * skin();
        for (int p : c.members) {
            if ((particles_.position[p] - rebuild_position_[p]).squaredNorm() > half_skin * half_skin) need_rebuild_ = true;
            if (!std::isfinite(particles_.position[p].squaredNorm()))
                throw SimulationError(step_, "non-finite position (NaN) of clump member " + std::to_string(p));
        }
    }
}

void World::move_walls() {
    const double dt = dt_;
    std::size_t k = 0;
    for (PlaneWall& w : plane_walls_) {
        if (track_energy_) energy_.boundary_work += -w.force.dot(w.velocity) * dt;
        w.point += w.velocity * dt;
        wall_travel_[k++] += w.velocity.norm() * dt;
    }
    for (CylinderWall& w : cylinder_walls_) {
        if (track_energy_) energy_.boundary_work += (-w.force.dot(w.velocity) - w.radial_force * w.radial_velocity) * dt;
        w.base += w.velocity * dt;
        w.radius += w.radial_velocity * dt;
        wall_travel_[k++] += (w.velocity.norm() + std::abs(w.radial_velocity)) * dt;
    }
    const double half_skin = 0.5 * skin();
    for (double travel : wall_travel_)
        if (travel > half_skin) need_rebuild_ = true;
}

void World::check_stability() {
    if (track_energy_ && energy_.kinetic > max_kinetic_) {
        std::ostringstream why;
        why << "exploding kinetic energy: " << energy_.kinetic << " J exceeds the limit " << max_kinetic_ << " J";
        throw SimulationError(step_, why.str());
    }
}

void World::finish_step(StepState& st) {
    finish_contact_forces(st);
    finish_particles(st);
    integrate_clumps(st.kinetic);
    move_walls();
    check_stability();
    ++step_;
    time_ += dt_;
}

void World::cycle(long n) {
    if (n < 0) throw InputError("cycle: field 'steps' must be >= 0, got " + std::to_string(n));
    if (n == 0) return;
    if (!(dt_ > 0)) throw InputError("cycle: time step not set; call set_time_step(critical_time_step()) first");
    if (particles_.size() == 0) throw InputError("cycle: the world has no particles");
    StepState st;

    const bool team = threads_ > 1 && static_cast<long>(particles_.size()) >= kParallelMin;
    long s = 0;
    while (s < n) {
        ensure_ready();
        if (need_rebuild_) rebuild_neighbors();  // serial merge; the cell search is parallel
        // A rebuild may meet a new group pair (a new resolved law).
        st.params.clear();
        for (const ContactLaw& l : resolved_laws_) st.params.push_back(LinearContact::Params::from(l));
        if (!team) {
            // One thread (or a model too small to share): the same phases in order.
            prepare_step(st, s + 1 == n);
            const long nc = st.contact_block_count, np = st.particle_block_count;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads_) if (threads_ > 1 && nc * kBlock >= kParallelMin)
            for (long b = 0; b < nc; ++b) contact_block(st, b);
            wall_contacts_pass(st);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads_) if (threads_ > 1 && np * kParticleBlock >= kParallelMin)
            for (long b = 0; b < np; ++b) particle_block(st, b);
            finish_step(st);
            ++s;
            continue;
        }
        // Thread team: one OpenMP region for a run of steps (until the neighbour list must be
        // rebuilt or the call ends), three barriers per step. A region per phase cost a fork
        // and a join each, i.e. four thread wake-ups per step (libgomp: a futex each under
        // OMP_WAIT_POLICY=passive); docs/engine.md, "Performance of the full-size paper group".
        // Blocks are handed out from both ends (TwoEndedBlocks) and reduced in block order,
        // so results equal the one-thread path.
        TwoEndedBlocks contact_blocks, particle_blocks;
        std::atomic<bool> leave{false};
        std::exception_ptr error;
        long done = s;
        prepare_step(st, done + 1 == n);
        contact_blocks.reset(st.contact_block_count);
        particle_blocks.reset(st.particle_block_count);
#pragma omp parallel num_threads(threads_)
        {
            const int tid = omp_get_thread_num(), nt = omp_get_num_threads();
            while (true) {
                // Contacts: the last thread takes the wall contacts first, then joins the blocks.
                if (tid == nt - 1) wall_contacts_pass(st);
                for (long b; (b = contact_blocks.take(tid)) >= 0;)
                    contact_block(st, b);
#pragma omp barrier
                for (long b; (b = particle_blocks.take(tid)) >= 0;)
                    particle_block(st, b);
#pragma omp barrier
                if (tid == 0) {
                    // Serial rest of the step, then the next step's set-up (others wait).
                    try {
                        finish_step(st);
                        ++done;
                        if (done >= n || need_rebuild_) leave.store(true, std::memory_order_relaxed);
                        else prepare_step(st, done + 1 == n);
                    } catch (...) {
                        error = std::current_exception();
                        leave.store(true, std::memory_order_relaxed);
                    }
                    contact_blocks.reset(st.contact_block_count);
                    particle_blocks.reset(st.particle_block_count);
                }
#pragma omp barrier
                if (leave.load(std::memory_order_relaxed)) break;
            }
        }
        if (error) std::rethrow_exception(error);
        s = done;
    }
}

}  // namespace triax
