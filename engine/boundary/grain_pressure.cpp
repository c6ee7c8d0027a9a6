#include "engine/boundary/grain_pressure.hpp"

#include <algorithm>
#include <cmath>

namespace triax::boundary {

namespace {
constexpr double kPi = 3.14159265358979323846;
// Depth below a cell's envelope, as a fraction of the cell size, within which grains share
// the cell's force.
constexpr double kShareDepth = 0.05;
}

GrainPressure::GrainPressure(int first, int count, double specimen_radius_m, double height_m, double cell_size_m)
    : first_(first), count_(count) {
    if (!(cell_size_m > 0.0)) throw InputError("grain pressure boundary: cell size must be > 0");
    share_depth_ = kShareDepth * cell_size_m;
    n_theta_ = std::max(8, static_cast<int>(std::ceil(2.0 * kPi * specimen_radius_m / cell_size_m)));
    n_z_ = std::max(2, static_cast<int>(std::ceil(height_m / cell_size_m)));
    const double dth = 2.0 * kPi / n_theta_;
    for (int k = 0; k < n_theta_; ++k) {
        edge_cos_.push_back(std::cos(k * dth));
        edge_sin_.push_back(std::sin(k * dth));
        centre_cos_.push_back(std::cos((k + 0.5) * dth));
        centre_sin_.push_back(std::sin((k + 0.5) * dth));
    }
}

template <class Visit>
void GrainPressure::for_each_reach(const World& world, double z_bottom, double z_top, double inner_m,
                                   Visit&& visit) const {
    const auto& p = world.particles();
    const double dth = 2.0 * kPi / n_theta_, dz = (z_top - z_bottom) / n_z_;
    for (int q = first_; q < first_ + count_; ++q) {
        const Vec3& c = p.position[q];
        const double a = p.radius[q];
        const double rc = std::hypot(c.x(), c.y());
        if (rc + a < inner_m) continue;
        const int iz0 = std::max(0, static_cast<int>(std::floor((c.z() - a - z_bottom) / dz)));
        const int iz1 = std::min(n_z_ - 1, static_cast<int>(std::floor((c.z() + a - z_bottom) / dz)));
        // Cells (unwrapped index k spans [k dth, (k + 1) dth]) within the grain's angular
        // reach; all of them for a grain on the axis.
        const double thc = std::atan2(c.y(), c.x());
        // Direction of the centre; a grain on the axis takes the x axis (atan2(0, 0) = 0).
        const double cos_c = rc > 0.0 ? c.x() / rc : 1.0, sin_c = rc > 0.0 ? c.y() / rc : 0.0;
        const double half = rc > a ? std::asin(a / rc) : kPi;
        const int k0 = static_cast<int>(std::floor((thc - half) / dth));
        const int k1 = std::min(k0 + n_theta_ - 1, static_cast<int>(std::floor((thc + half) / dth)));
        for (int iz = iz0; iz <= iz1; ++iz) {
            // The grain's point nearest to the cell in height, then in angle: its exit radius
            // there is the farthest the grain reaches out within the cell.
            const double z_near = std::clamp(c.z(), z_bottom + iz * dz, z_bottom + (iz + 1) * dz);
            const double h = c.z() - z_near;
            const double a_row2 = a * a - h * h;  // squared radius of the grain's section there
            if (a_row2 <= 0.0) continue;
            for (int k = k0; k <= k1; ++k) {
                // The ray nearest the centre within the cell: the centre's own when the cell
                // holds it, else the nearer edge (k or k + 1), at angle th - thc from it.
                double cos_d = 1.0, sin_d = 0.0;  // cos, sin of th - thc
                const bool below = thc < k * dth, above = thc > (k + 1) * dth;
                if (below || above) {
                    const int e = wrap(below ? k : k + 1);
                    cos_d = edge_cos_[e] * cos_c + edge_sin_[e] * sin_c;
                    sin_d = edge_sin_[e] * cos_c - edge_cos_[e] * sin_c;
                }
                const double t = rc * cos_d;  // centre's distance along the ray
                const double off = rc * sin_d;
                if (off * off >= a_row2) continue;
                const int around = wrap(k);
                visit(q, around, static_cast<std::size_t>(iz) * n_theta_ + around, t + std::sqrt(a_row2 - off * off));
            }
        }
    }
}

std::vector<double> GrainPressure::envelope(const World& world, double z_bottom, double z_top) const {
    std::vector<double> rho(static_cast<std::size_t>(n_theta_) * n_z_, 0.0);
    for_each_reach(world, z_bottom, z_top, -1.0,
                   [&](int, int, std::size_t cell, double r) { rho[cell] = std::max(rho[cell], r); });
    return rho;
}

void GrainPressure::collect_reaches(const World& world, double z_bottom, double z_top, double inner_m) {
    reaches_.clear();
    rho_.assign(static_cast<std::size_t>(n_theta_) * n_z_, 0.0);
    for_each_reach(world, z_bottom, z_top, inner_m, [&](int q, int around, std::size_t cell, double r) {
        reaches_.push_back({q, around, cell, r});
        rho_[cell] = std::max(rho_[cell], r);
    });
}

double GrainPressure::apply_pressure(World& world, double pressure_pa, double z_bottom, double z_top) {
    // Every (grain, cell, reach) once: the envelope, the shares and the forces all read it.
    // The skipped interior grains reach at most inner_m_; the skip is exact when every cell's
    // envelope lies 1.5 sharing depths above that (their weights are then max(0, < -0.5) = 0
    // and they set no envelope), else every grain is visited.
    collect_reaches(world, z_bottom, z_top, inner_m_);
    double lowest = *std::min_element(rho_.begin(), rho_.end());
    if (inner_m_ >= 0.0 && lowest < inner_m_ + 1.5 * share_depth_) {
        collect_reaches(world, z_bottom, z_top, -1.0);
        lowest = *std::min_element(rho_.begin(), rho_.end());
    }
    // The next call's bound: 1.5 sharing depths of room for the grains' motion between calls
    // (a few um in 10 DEM steps against share_depth_ = 0.05 cell).
    inner_m_ = lowest - 3.0 * share_depth_;
    // The grains within `share_depth_` of a cell's envelope share its force, weighted
    // 1 - depth / share_depth_: the force moves continuously from grain to grain as they
    // move, instead of jumping to whichever is outermost by a hair (which kept consolidation
    // from settling).
    auto weight = [&](const Reach& r) { return std::max(0.0, 1.0 - (rho_[r.cell] - r.rho) / share_depth_); };
    weight_sum_.assign(rho_.size(), 0.0);
    for (const Reach& r : reaches_) weight_sum_[r.cell] += weight(r);
    auto& p = world.particles();
    for (int q = first_; q < first_ + count_; ++q) p.external_force[q].setZero();
    const double dth = 2.0 * kPi / n_theta_, dz = (z_top - z_bottom) / n_z_;
    double total = 0.0;
    for (const Reach& r : reaches_) {
        const double w = weight(r);
        if (w <= 0.0) continue;
        const std::size_t it = static_cast<std::size_t>(r.around);
        const double f = pressure_pa * rho_[r.cell] * dth * dz * w / weight_sum_[r.cell];  // N, the grain's share of the cell
        p.external_force[r.grain] -= f * Vec3(centre_cos_[it], centre_sin_[it], 0.0);
        total += f;
    }
    return total;
}

double GrainPressure::enclosed_volume(const World& world, double z_bottom, double z_top) const {
    const std::vector<double> rho_cells = envelope(world, z_bottom, z_top);
    const double dth = 2.0 * kPi / n_theta_, dz = (z_top - z_bottom) / n_z_;
    double v = 0.0;
    for (int iz = 0; iz < n_z_; ++iz) {
        double sum = 0.0, sum2 = 0.0;
        int n = 0;
        for (int it = 0; it < n_theta_; ++it) {
            const double rho = rho_cells[static_cast<std::size_t>(iz) * n_theta_ + it];
            if (rho <= 0.0) continue;
            sum += rho;
            sum2 += rho * rho;
            ++n;
        }
        if (n == 0) continue;
        const double mean = sum / n;
        v += 0.5 * dth * dz * (sum2 + (n_theta_ - n) * mean * mean);
    }
    return v;
}

double GrainPressure::mean_radius(const World& world, double z_bottom, double z_top) const {
    const std::vector<double> rho_cells = envelope(world, z_bottom, z_top);
    double sum = 0.0;
    int n = 0;
    for (double rho : rho_cells)
        if (rho > 0.0) {
            sum += rho;
            ++n;
        }
    return n ? sum / n : 0.0;
}

}  // namespace triax::boundary
