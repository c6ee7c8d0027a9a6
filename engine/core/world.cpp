// World: model building, contact-law resolution, neighbour-list rebuild with history
// merge, bond installation and the global measures. The step itself is in world_step.cpp.
#include "engine/core/world.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>

namespace triax {

namespace {
bool finite(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }
}  // namespace

int World::add_sphere(const Vec3& position, double radius, double density, int group) {
    if (!finite(position)) throw InputError("add_sphere: field 'position' must be finite");
    if (!(radius > 0) || !std::isfinite(radius)) throw InputError("add_sphere: field 'radius' must be > 0 m, got " + std::to_string(radius));
    if (!(density > 0) || !std::isfinite(density)) throw InputError("add_sphere: field 'density' must be > 0 kg/m^3, got " + std::to_string(density));
    min_radius_ = std::min(min_radius_, radius);
    need_rebuild_ = true;
    return particles_.add(position, radius, density, group);
}

int World::add_plane_wall(const Vec3& point, const Vec3& normal, int group) {
    if (!finite(point)) throw InputError("add_plane_wall: field 'point' must be finite");
    if (!finite(normal) || normal.norm() == 0.0) throw InputError("add_plane_wall: field 'normal' must be a non-zero vector");
    PlaneWall w;
    w.point = point;
    w.normal = normal.normalized();
    w.group = group;
    plane_walls_.push_back(w);
    need_rebuild_ = true;
    return static_cast<int>(plane_walls_.size() - 1);
}

int World::add_cylinder_wall(const Vec3& base, const Vec3& axis, double radius, double height, int group) {
    if (!finite(base)) throw InputError("add_cylinder_wall: field 'base' must be finite");
    if (!finite(axis) || axis.norm() == 0.0) throw InputError("add_cylinder_wall: field 'axis' must be a non-zero vector");
    if (!(radius > 0)) throw InputError("add_cylinder_wall: field 'radius' must be > 0 m");
    if (!(height > 0)) throw InputError("add_cylinder_wall: field 'height' must be > 0 m");
    CylinderWall w;
    w.base = base;
    w.axis = axis.normalized();
    w.radius = radius;
    w.height = height;
    w.group = group;
    cylinder_walls_.push_back(w);
    need_rebuild_ = true;
    return static_cast<int>(cylinder_walls_.size() - 1);
}

int World::add_clump(const std::vector<int>& members) {
    if (members.empty()) throw InputError("add_clump: field 'members' is empty");
    const int id = static_cast<int>(clumps_.size());
    Clump c;
    c.members = members;
    double m = 0.0;
    Vec3 com = Vec3::Zero();
    for (int p : members) {
        if (p < 0 || p >= static_cast<int>(particles_.size()))
            throw InputError("add_clump: member index " + std::to_string(p) + " does not exist");
        if (particles_.clump_id[p] >= 0)
            throw InputError("add_clump: sphere " + std::to_string(p) + " already belongs to clump " + std::to_string(particles_.clump_id[p]));
        m += particles_.mass[p];
        com += particles_.mass[p] * particles_.position[p];
    }
    com /= m;
    // Inertia of the member spheres about the centre of mass (overlaps counted twice,
    // as PFC does for clumps built from pebbles without a volume correction).
    Mat3 inertia = Mat3::Zero();
    for (int p : members) {
        const Vec3 r = particles_.position[p] - com;
        inertia += particles_.inertia[p] * Mat3::Identity() +
                   particles_.mass[p] * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
        c.body_offsets.push_back(r);
        particles_.clump_id[p] = id;
        particles_.flags[p] |= kClumpMember;
    }
    c.position = com;
    c.mass = m;
    c.inertia_body = inertia;
    Vec3 v = Vec3::Zero();
    for (int p : members) v += particles_.mass[p] * particles_.velocity[p];
    c.velocity = v / m;
    clumps_.push_back(c);
    update_clump_members(clumps_.back());
    need_rebuild_ = true;
    return id;
}

void World::set_clump_velocity(int k, const Vec3& velocity, const Vec3& angular_velocity) {
    Clump& c = clumps_.at(k);
    c.velocity = velocity;
    c.angular_velocity = angular_velocity;
    update_clump_members(c);
}

void World::update_clump_members(Clump& c) {
    const Mat3 rot = c.orientation.toRotationMatrix();
    for (std::size_t m = 0; m < c.members.size(); ++m) {
        const int p = c.members[m];
        const Vec3 arm = rot * c.body_offsets[m];
        particles_.position[p] = c.position + arm;
        particles_.velocity[p] = c.velocity + c.angular_velocity.cross(arm);
        particles_.angular_velocity[p] = c.angular_velocity;
    }
}

void World::set_default_contact_law(const ContactLaw& law) {
    laws_.set_default(law);
    refresh_resolved_laws();
}

void World::set_contact_law(int group_a, int group_b, const ContactLaw& law) {
    laws_.set(group_a, group_b, law);
    refresh_resolved_laws();
}

// Existing contacts keep their law index; the parameters behind it are refreshed, so
// contact_law_of() stays valid between a law change and the next step.
void World::refresh_resolved_laws() {
    any_rolling_ = false;
    for (std::size_t k = 0; k < resolved_keys_.size(); ++k) {
        resolved_laws_[k] = laws_.get(resolved_keys_[k].first, resolved_keys_[k].second);
        if (resolved_laws_[k].needs_rolling()) any_rolling_ = true;
    }
}

int World::law_index(int a, int b) {
    const std::pair<int, int> key = a < b ? std::make_pair(a, b) : std::make_pair(b, a);
    for (std::size_t k = 0; k < resolved_keys_.size(); ++k)
        if (resolved_keys_[k] == key) return static_cast<int>(k);
    resolved_keys_.push_back(key);
    resolved_laws_.push_back(laws_.get(a, b));
    if (resolved_laws_.back().needs_rolling()) any_rolling_ = true;
    return static_cast<int>(resolved_keys_.size() - 1);
}

void World::set_time_step(double dt) {
    if (!(dt > 0) || !std::isfinite(dt)) throw InputError("set_time_step: field 'dt' must be > 0 s, got " + std::to_string(dt));
    dt_ = dt;
}

void World::set_local_damping(double alpha) {
    if (!(alpha >= 0 && alpha < 1)) throw InputError("set_local_damping: field 'alpha' must be in [0, 1), got " + std::to_string(alpha));
    alpha_ = alpha;
}

void World::set_threads(int n) {
    if (n < 1) throw InputError("set_threads: field 'threads' must be >= 1, got " + std::to_string(n));
    threads_ = n;
}

void World::set_skin(double skin) {
    if (!(skin > 0)) throw InputError("set_skin: field 'skin' must be > 0 m");
    skin_ = skin;
    need_rebuild_ = true;
}

double World::skin() const {
    if (skin_) return *skin_;
    return std::isfinite(min_radius_) ? 0.1 * min_radius_ : 1e-3;
}

void World::set_domain(const Vec3& lo, const Vec3& hi) {
    if (!(lo.array() < hi.array()).all()) throw InputError("set_domain: field 'lo' must be below 'hi' on every axis");
    domain_ = std::make_pair(lo, hi);
}

void World::ensure_ready() {
    const std::size_t n = particles_.size();
    if (rebuild_position_.size() != n) need_rebuild_ = true;
    inertial_mass_.resize(n);
    inertial_inertia_.resize(n);
    stiffness_sum_.resize(n);
    rot_stiffness_sum_.resize(n);
}

// Rebuilds the candidate pair list and merges the old history into it by key.
void World::rebuild_neighbors() {
    const int n = static_cast<int>(particles_.size());
    const double skin = this->skin();
    std::vector<int> pi, pj;
    cells_.build(particles_.position, particles_.radius, particles_.clump_id, skin, threads_, pi, pj);

    // Bonded pairs that drifted beyond the skin stay contacts.
    std::vector<std::pair<int, int>> extra;
    {
        std::size_t a = 0;
        for (std::size_t k = 0; k < contacts_.size(); ++k) {
            if (!contacts_.bonded[k]) continue;
            const std::pair<int, int> key{contacts_.i[k], contacts_.j[k]};
            while (a < pi.size() && std::make_pair(pi[a], pj[a]) < key) ++a;
            if (a >= pi.size() || std::make_pair(pi[a], pj[a]) != key) extra.push_back(key);
        }
    }
    if (!extra.empty()) {
        std::vector<std::pair<int, int>> all;
        all.reserve(pi.size() + extra.size());
        for (std::size_t k = 0; k < pi.size(); ++k) all.emplace_back(pi[k], pj[k]);
        all.insert(all.end(), extra.begin(), extra.end());
        std::sort(all.begin(), all.end());
        pi.resize(all.size());
        pj.resize(all.size());
        for (std::size_t k = 0; k < all.size(); ++k) { pi[k] = all[k].first; pj[k] = all[k].second; }
    }

    ContactStore next;
    next.resize(pi.size());
    std::size_t old = 0;
    for (std::size_t k = 0; k < pi.size(); ++k) {
        next.i[k] = pi[k];
        next.j[k] = pj[k];
        next.law[k] = law_index(particles_.group[pi[k]], particles_.group[pj[k]]);
        const std::pair<int, int> key{pi[k], pj[k]};
        while (old < contacts_.size() && std::make_pair(contacts_.i[old], contacts_.j[old]) < key) ++old;
        if (old < contacts_.size() && contacts_.i[old] == pi[k] && contacts_.j[old] == pj[k])
            next.copy_history(k, contacts_, old);
        else
            next.reset_history(k);
        next.force_on_j[k].setZero();
        next.torque_on_i[k].setZero();
        next.torque_on_j[k].setZero();
        next.overlap[k] = 0.0;
        next.contact_point[k].setZero();
    }
    contacts_ = std::move(next);

    // Wall candidates, sorted by (particle, kind, wall).
    WallContactStore wnext;
    {
        std::vector<int> wp, ww;
        std::vector<std::uint8_t> wk;
        for (int p = 0; p < n; ++p) {
            const Vec3& x = particles_.position[p];
            const double r = particles_.radius[p];
            for (std::size_t w = 0; w < plane_walls_.size(); ++w) {
                const PlaneWall& pw = plane_walls_[w];
                if ((x - pw.point).dot(pw.normal) - r < skin) { wp.push_back(p); wk.push_back(0); ww.push_back(static_cast<int>(w)); }
            }
            for (std::size_t w = 0; w < cylinder_walls_.size(); ++w) {
                const CylinderWall& cw = cylinder_walls_[w];
                const Vec3 rel = x - cw.base;
                const double a = rel.dot(cw.axis);
                const double rho = (rel - a * cw.axis).norm();
                if (a > -skin && a < cw.height + skin && cw.radius - rho - r < skin) {
                    wp.push_back(p); wk.push_back(1); ww.push_back(static_cast<int>(w));
                }
            }
        }
        wnext.resize(wp.size());
        std::size_t o = 0;
        auto key_of = [](int p, int kind, int w) { return std::make_tuple(p, kind, w); };
        for (std::size_t k = 0; k < wp.size(); ++k) {
            wnext.particle[k] = wp[k];
            wnext.wall_kind[k] = wk[k];
            wnext.wall[k] = ww[k];
            const int wgroup = wk[k] == 0 ? plane_walls_[ww[k]].group : cylinder_walls_[ww[k]].group;
            wnext.law[k] = law_index(particles_.group[wp[k]], wgroup);
            const auto key = key_of(wp[k], wk[k], ww[k]);
            while (o < wall_contacts_.size() &&
                   key_of(wall_contacts_.particle[o], wall_contacts_.wall_kind[o], wall_contacts_.wall[o]) < key) ++o;
            if (o < wall_contacts_.size() &&
                key_of(wall_contacts_.particle[o], wall_contacts_.wall_kind[o], wall_contacts_.wall[o]) == key)
                wnext.copy_history(k, wall_contacts_, o);
            else
                wnext.reset_history(k);
            wnext.force_on_particle[k].setZero();
            wnext.torque_on_particle[k].setZero();
            wnext.contact_point[k].setZero();
            wnext.overlap[k] = 0.0;
        }
    }
    wall_contacts_ = std::move(wnext);

    // Gather lists: per particle, its slots in increasing slot order (fixed order).
    adj_start_.assign(n + 1, 0);
    for (std::size_t k = 0; k < contacts_.size(); ++k) { ++adj_start_[contacts_.i[k] + 1]; ++adj_start_[contacts_.j[k] + 1]; }
    for (int p = 0; p < n; ++p) adj_start_[p + 1] += adj_start_[p];
    adj_.resize(adj_start_[n]);
    {
        std::vector<int> fill(adj_start_.begin(), adj_start_.end() - 1);
        for (std::size_t k = 0; k < contacts_.size(); ++k) {
            adj_[fill[contacts_.i[k]]++] = static_cast<int>(2 * k);
            adj_[fill[contacts_.j[k]]++] = static_cast<int>(2 * k + 1);
        }
    }
    wall_adj_start_.assign(n + 1, 0);
    for (std::size_t k = 0; k < wall_contacts_.size(); ++k) ++wall_adj_start_[wall_contacts_.particle[k] + 1];
    for (int p = 0; p < n; ++p) wall_adj_start_[p + 1] += wall_adj_start_[p];
    wall_adj_.resize(wall_adj_start_[n]);
    {
        std::vector<int> fill(wall_adj_start_.begin(), wall_adj_start_.end() - 1);
        for (std::size_t k = 0; k < wall_contacts_.size(); ++k) wall_adj_[fill[wall_contacts_.particle[k]]++] = static_cast<int>(k);
    }

    rebuild_position_ = particles_.position;
    wall_travel_.assign(plane_walls_.size() + cylinder_walls_.size(), 0.0);
    need_rebuild_ = false;
    ++rebuilds_;
}

int World::bond_contacts(int group_a, int group_b, double gap_tolerance, double normal_strength,
                         double shear_strength) {
    if (!(gap_tolerance >= 0)) throw InputError("bond_contacts: field 'gap_tolerance' must be >= 0 m");
    if (!(normal_strength >= 0)) throw InputError("bond_contacts: field 'normal_strength' must be >= 0 N");
    if (!(shear_strength >= 0)) throw InputError("bond_contacts: field 'shear_strength' must be >= 0 N");
    ensure_ready();
    // Search with a skin at least as wide as the tolerance so no candidate is missed.
    const std::optional<double> saved = skin_;
    skin_ = std::max(skin(), gap_tolerance * 1.0001);
    rebuild_neighbors();
    skin_ = saved;
    int count = 0;
    for (std::size_t k = 0; k < contacts_.size(); ++k) {
        const int i = contacts_.i[k], j = contacts_.j[k];
        const int gi = particles_.group[i], gj = particles_.group[j];
        if (!((gi == group_a && gj == group_b) || (gi == group_b && gj == group_a))) continue;
        const double gap = (particles_.position[j] - particles_.position[i]).norm() - particles_.radius[i] - particles_.radius[j];
        if (gap > gap_tolerance) continue;
        if (!contacts_.bonded[k]) ++count;
        contacts_.bonded[k] = 1;
        contacts_.active[k] = 1;
        contacts_.bond_normal_strength[k] = normal_strength;
        contacts_.bond_shear_strength[k] = shear_strength;
        contacts_.damage[k] = 0.0;
        if (gap > 0) {
            // Start unloaded: the law sees overlap = -gap + reference_gap = 0.
            contacts_.reference_gap[k] = gap;
            contacts_.shear_force[k].setZero();
            contacts_.normal_force[k] = 0.0;
        }
    }
    // The next regular rebuild uses the ordinary skin; bonded pairs are kept regardless.
    need_rebuild_ = false;
    return count;
}

long World::intact_bond_count() const {
    long c = 0;
    for (std::size_t k = 0; k < contacts_.size(); ++k) c += contacts_.bonded[k];
    return c;
}

long World::active_contact_count() const {
    long c = 0;
    for (std::size_t k = 0; k < contacts_.size(); ++k) c += contacts_.active[k];
    return c;
}

long World::active_wall_contact_count() const {
    long c = 0;
    for (std::size_t k = 0; k < wall_contacts_.size(); ++k) c += wall_contacts_.active[k];
    return c;
}

double World::contact_stiffness_fallback(int group) const {
    double k = laws_.default_law().kn + laws_.default_law().ks;
    for (const auto& [key, law] : laws_.entries())
        if (key.first == group || key.second == group) k = std::max(k, law.kn + law.ks);
    for (const auto& w : plane_walls_) k = std::max(k, laws_.get(group, w.group).kn + laws_.get(group, w.group).ks);
    for (const auto& w : cylinder_walls_) k = std::max(k, laws_.get(group, w.group).kn + laws_.get(group, w.group).ks);
    return k;
}

double World::critical_time_step(double safety) const {
    const std::size_t n = particles_.size();
    std::vector<double> kt(n, 0.0), kr(n, 0.0);
    for (std::size_t k = 0; k < contacts_.size(); ++k) {
        if (!contacts_.active[k] || contacts_.law[k] >= static_cast<int>(resolved_laws_.size())) continue;
        const ContactLaw& law = resolved_laws_[contacts_.law[k]];
        for (int p : {contacts_.i[k], contacts_.j[k]}) {
            kt[p] += law.kn + law.ks;
            kr[p] += law.ks * particles_.radius[p] * particles_.radius[p];
        }
    }
    for (std::size_t k = 0; k < wall_contacts_.size(); ++k) {
        if (!wall_contacts_.active[k] || wall_contacts_.law[k] >= static_cast<int>(resolved_laws_.size())) continue;
        const ContactLaw& law = resolved_laws_[wall_contacts_.law[k]];
        const int p = wall_contacts_.particle[k];
        kt[p] += law.kn + law.ks;
        kr[p] += law.ks * particles_.radius[p] * particles_.radius[p];
    }
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t p = 0; p < n; ++p) {
        if (particles_.clump_id[p] >= 0) continue;
        double k = kt[p];
        double krot = kr[p];
        if (k == 0.0) {
            k = contact_stiffness_fallback(particles_.group[p]);
            krot = 0.5 * k * particles_.radius[p] * particles_.radius[p];
        }
        best = std::min(best, std::sqrt(particles_.mass[p] / k));
        if (krot > 0) best = std::min(best, std::sqrt(particles_.inertia[p] / krot));
    }
    for (const Clump& c : clumps_) {
        double k = 0.0;
        double krot = 0.0;
        for (int p : c.members) { k += kt[p]; krot += kr[p]; }
        if (k == 0.0) k = contact_stiffness_fallback(particles_.group[c.members.front()]);
        best = std::min(best, std::sqrt(c.mass / k));
        if (krot > 0 && !c.fix_rotation) {
            const double i_min = c.inertia_body.selfadjointView<Eigen::Lower>().eigenvalues().minCoeff();
            best = std::min(best, std::sqrt(i_min / krot));
        }
    }
    if (!std::isfinite(best)) throw InputError("critical_time_step: the world has no particles");
    return safety * best;
}

double World::kinetic_energy() const {
    double e = 0.0;
    for (std::size_t p = 0; p < particles_.size(); ++p) {
        if (particles_.clump_id[p] >= 0) continue;
        e += 0.5 * particles_.mass[p] * particles_.velocity[p].squaredNorm() +
             0.5 * particles_.inertia[p] * particles_.angular_velocity[p].squaredNorm();
    }
    for (const Clump& c : clumps_) {
        if (c.control != ClumpControl::Free) continue;
        const Mat3 rot = c.orientation.toRotationMatrix();
        e += 0.5 * c.mass * c.velocity.squaredNorm() +
             0.5 * c.angular_velocity.dot(rot * c.inertia_body * rot.transpose() * c.angular_velocity);
    }
    return e;
}

double World::mean_unbalanced_force() const {
    double sum = 0.0;
    long count = 0;
    for (std::size_t p = 0; p < particles_.size(); ++p) {
        if (particles_.flags[p] & (kClumpMember | kFixedVelocity)) continue;
        sum += particles_.force[p].norm();
        ++count;
    }
    for (const Clump& c : clumps_) {
        if (c.control != ClumpControl::Free) continue;
        Vec3 f = c.applied_force;
        for (int p : c.members) f += particles_.force[p];
        sum += f.norm();
        ++count;
    }
    return count ? sum / count : 0.0;
}

double World::mean_contact_force() const {
    double sum = 0.0;
    long count = 0;
    for (std::size_t k = 0; k < contacts_.size(); ++k)
        if (contacts_.active[k]) { sum += contacts_.force_on_j[k].norm(); ++count; }
    for (std::size_t k = 0; k < wall_contacts_.size(); ++k)
        if (wall_contacts_.active[k]) { sum += wall_contacts_.force_on_particle[k].norm(); ++count; }
    return count ? sum / count : 0.0;
}

double World::unbalanced_force_ratio() const {
    const double c = mean_contact_force();
    return c > 0 ? mean_unbalanced_force() / c : 0.0;
}

}  // namespace triax
