#include "engine/measure/measurement_sphere.hpp"

#include <algorithm>
#include <cmath>

namespace triax {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

MeasurementSphere::MeasurementSphere(const Vec3& center, double radius) : center_(center), radius_(radius) {
    if (!(radius > 0)) throw InputError("MeasurementSphere: field 'radius' must be > 0 m");
    if (!std::isfinite(center.squaredNorm())) throw InputError("MeasurementSphere: field 'center' must be finite");
}

double MeasurementSphere::volume() const { return 4.0 / 3.0 * kPi * radius_ * radius_ * radius_; }

double MeasurementSphere::intersection_volume(double r1, double r2, double d) {
    if (d >= r1 + r2) return 0.0;
    const double rs = std::min(r1, r2);
    if (d <= std::abs(r1 - r2)) return 4.0 / 3.0 * kPi * rs * rs * rs;
    const double h = r1 + r2 - d;
    return kPi * h * h * (d * d + 2.0 * d * (r1 + r2) - 3.0 * (r1 - r2) * (r1 - r2)) / (12.0 * d);
}

void MeasurementSphere::set_reference(const World& world) {
    const ParticleArrays& pa = world.particles();
    reference_members_.clear();
    reference_positions_.clear();
    for (std::size_t p = 0; p < pa.size(); ++p) {
        if ((pa.position[p] - center_).norm() < radius_) {
            reference_members_.push_back(static_cast<int>(p));
            reference_positions_.push_back(pa.position[p]);
        }
    }
}

MeasurementReading MeasurementSphere::measure(const World& world) const {
    const ParticleArrays& pa = world.particles();
    const std::size_t n = pa.size();
    MeasurementReading r;
    std::vector<char> inside(n, 0);
    double solid = 0.0, vp_inside = 0.0;
    for (std::size_t p = 0; p < n; ++p) {
        const double d = (pa.position[p] - center_).norm();
        solid += intersection_volume(radius_, pa.radius[p], d);
        if (d < radius_) {
            inside[p] = 1;
            ++r.particle_count;
            vp_inside += 4.0 / 3.0 * kPi * std::pow(pa.radius[p], 3);
            r.mean_angular_velocity += pa.angular_velocity[p];
        }
    }
    r.porosity = 1.0 - solid / volume();
    if (r.particle_count > 0) r.mean_angular_velocity /= r.particle_count;

    long contacts = 0;
    Mat3 sum = Mat3::Zero();
    const ContactStore& c = world.contacts();
    for (std::size_t k = 0; k < c.size(); ++k) {
        if (!c.active[k]) continue;
        const int i = c.i[k], j = c.j[k];
        const Vec3& f = c.force_on_j[k];
        if (inside[i]) { ++contacts; sum += (c.contact_point[k] - pa.position[i]) * (-f).transpose(); }
        if (inside[j]) { ++contacts; sum += (c.contact_point[k] - pa.position[j]) * f.transpose(); }
    }
    const WallContactStore& w = world.wall_contacts();
    for (std::size_t k = 0; k < w.size(); ++k) {
        if (!w.active[k] || !inside[w.particle[k]]) continue;
        ++contacts;
        sum += (w.contact_point[k] - pa.position[w.particle[k]]) * w.force_on_particle[k].transpose();
    }
    if (r.particle_count > 0) {
        r.coordination = static_cast<double>(contacts) / r.particle_count;
        const Mat3 sym = 0.5 * (sum + sum.transpose());
        r.stress = -(1.0 - r.porosity) / vp_inside * sym;
    }

    if (!reference_members_.empty()) {
        for (std::size_t m = 0; m < reference_members_.size(); ++m) {
            const int p = reference_members_[m];
            if (static_cast<std::size_t>(p) < n) r.mean_displacement += pa.position[p] - reference_positions_[m];
        }
        r.mean_displacement /= static_cast<double>(reference_members_.size());
    }
    return r;
}

}  // namespace triax
