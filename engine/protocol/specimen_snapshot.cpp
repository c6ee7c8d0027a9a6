#include "engine/protocol/specimen_snapshot.hpp"

#include <algorithm>

#include "engine/core/world.hpp"
#include "engine/protocol/specimen.hpp"

namespace triax::protocol {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

std::size_t SpecimenSnapshot::count_of(int g) const {
    return static_cast<std::size_t>(std::count(group.begin(), group.end(), g));
}

std::vector<SnapshotSphere> measurement_sphere_layout(const TestScheme& scheme, double mean_diameter_m) {
    const double H = scheme.specimen.height_m;
    const double r = std::max(0.15 * scheme.specimen.diameter_m, 1.5 * mean_diameter_m);
    std::vector<SnapshotSphere> out;
    for (double z : {0.4 * H, 0.0, -0.4 * H}) out.push_back({Vec3(0, 0, z), r});
    return out;
}

SpecimenSnapshot snapshot_of_world(const World& w, const std::string& stage, const std::vector<Vec3>& reference,
                                   const std::vector<Vec3>& rotation, const std::vector<std::uint8_t>& crushed) {
    const auto& p = w.particles();
    const std::size_t n = p.size();
    SpecimenSnapshot s;
    s.stage = stage;
    s.step = w.step();
    s.position = p.position;
    s.radius = p.radius;
    s.group = p.group;
    s.velocity = p.velocity;
    s.angular_velocity = p.angular_velocity;
    s.mass = p.mass;
    s.inertia = p.inertia;
    s.density.resize(n);
    s.displacement.assign(n, Vec3::Zero());
    s.rotation.assign(n, Vec3::Zero());
    s.crushed.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const double r = p.radius[i];
        s.density[i] = p.mass[i] / (4.0 / 3.0 * kPi * r * r * r);
        if (i < reference.size()) s.displacement[i] = p.position[i] - reference[i];
        if (i < rotation.size()) s.rotation[i] = rotation[i];
        if (i < crushed.size()) s.crushed[i] = crushed[i];
    }
    const auto& c = w.contacts();
    for (std::size_t k = 0; k < c.size(); ++k) {
        if (!c.active[k] && !c.bonded[k]) continue;
        s.contact_i.push_back(c.i[k]);
        s.contact_j.push_back(c.j[k]);
        s.bonded.push_back(c.bonded[k]);
        s.normal_force_n.push_back(c.normal_force[k]);
        s.shear_force_n.push_back(c.shear_force[k]);
        s.bond_normal_strength_n.push_back(c.bonded[k] ? c.bond_normal_strength[k] * (1.0 - c.damage[k]) : 0.0);
        s.bond_shear_strength_n.push_back(c.bonded[k] ? c.bond_shear_strength[k] * (1.0 - c.damage[k]) : 0.0);
    }
    for (std::size_t k = 0; k < w.plane_wall_count(); ++k) {
        const auto& pw = w.plane_wall(static_cast<int>(k));
        s.platens.push_back({"wall-" + std::to_string(k), pw.point, pw.normal, -pw.force.dot(pw.normal)});
    }
    return s;
}

SpecimenSnapshot snapshot_of(const Specimen& sp, const TestScheme& scheme, const std::string& stage) {
    const World& w = sp.world();
    std::vector<std::uint8_t> crushed(w.particle_count(), 0);
    if (sp.crushing_on()) {
        // A crushed grain contact keeps its plastic overlap (grain_crushing.hpp): both
        // grains of such a contact have crushed.
        const auto& c = w.contacts();
        for (std::size_t k = 0; k < c.size(); ++k)
            if (c.active[k] && c.plastic_overlap[k] > 0.0 && c.i[k] < sp.soil_count() && c.j[k] < sp.soil_count())
                crushed[c.i[k]] = crushed[c.j[k]] = 1;
    }
    SpecimenSnapshot s = snapshot_of_world(w, stage, sp.reference_positions(), sp.rotation(), crushed);
    if (s.platens.size() >= 2) {
        s.platens[sp.bottom_wall()].name = "bottom";
        s.platens[sp.top_wall()].name = "top";
    }
    s.measurement_spheres = measurement_sphere_layout(scheme, sp.mean_diameter());
    s.sizing_mean_radius_m = sp.sizing_mean_radius();
    s.sizing_min_radius_m = sp.sizing_min_radius();
    s.group_names = {"grain", "membrane", "platen"};
    return s;
}

}  // namespace triax::protocol
