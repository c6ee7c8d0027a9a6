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
}

template <class Visit>
void GrainPressure::for_each_reach(const World& world, double z_bottom, double z_top, Visit&& visit) const {
    const auto& p = world.particles();
    const double dth = 2.0 * kPi / n_theta_, dz = (z_top - z_bottom) / n_z_;
    for (int q = first_; q < first_ + count_; ++q) {
        const Vec3& c = p.position[q];
        const double a = p.radius[q];
        const double rc = std::hypot(c.x(), c.y());
        const int iz0 = std::max(0, static_cast<int>(std::floor((c.z() - a - z_bottom) / dz)));
        const int iz1 = std::min(n_z_ - 1, static_cast<int>(std::floor((c.z() + a - z_bottom) / dz)));
        // Cells (unwrapped index k spans [k dth, (k + 1) dth]) within the grain's angular
        // reach; all of them for a grain on the axis.
        const double thc = std::atan2(c.y(), c.x());
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
                const double th = std::clamp(thc, k * dth, (k + 1) * dth);
                const double t = rc * std::cos(th - thc);  // centre's distance along the ray
                const double off = rc * std::sin(th - thc);
                if (off * off >= a_row2) continue;
                visit(q, static_cast<std::size_t>(iz) * n_theta_ + ((k % n_theta_) + n_theta_) % n_theta_,
                      t + std::sqrt(a_row2 - off * off));
            }
        }
    }
}

std::vector<double> GrainPressure::envelope(const World& world, double z_bottom, double z_top) const {
    std::vector<double> rho(static_cast<std::size_t>(n_theta_) * n_z_, 0.0);
    for_each_reach(world, z_bottom, z_top, [&](int, std::size_t cell, double r) { rho[cell] = std::max(rho[cell], r); });
    return rho;
}

double GrainPressure::apply_pressure(World& world, double pressure_pa, double z_bottom, double z_top) const {
    // Every (grain, cell, reach) once: the envelope, the shares and the forces all read it.
    struct Reach {
        int grain;
        std::size_t cell;
        double rho;  // m
    };
    std::vector<Reach> reaches;
    std::vector<double> rho(static_cast<std::size_t>(n_theta_) * n_z_, 0.0);
    for_each_reach(world, z_bottom, z_top, [&](int q, std::size_t cell, double r) {
        reaches.push_back({q, cell, r});
        rho[cell] = std::max(rho[cell], r);
    });
    // The grains within `share_depth_` of a cell's envelope share its force, weighted
    // 1 - depth / share_depth_: the force moves continuously from grain to grain as they
    // move, instead of jumping to whichever is outermost by a hair (which kept consolidation
    // from settling).
    auto weight = [&](const Reach& r) { return std::max(0.0, 1.0 - (rho[r.cell] - r.rho) / share_depth_); };
    std::vector<double> weight_sum(rho.size(), 0.0);
    for (const Reach& r : reaches) weight_sum[r.cell] += weight(r);
    auto& p = world.particles();
    for (int q = first_; q < first_ + count_; ++q) p.external_force[q].setZero();
    const double dth = 2.0 * kPi / n_theta_, dz = (z_top - z_bottom) / n_z_;
    double total = 0.0;
    for (const Reach& r : reaches) {
        const double w = weight(r);
        if (w <= 0.0) continue;
        const double th = (static_cast<double>(r.cell % n_theta_) + 0.5) * dth;
        const double f = pressure_pa * rho[r.cell] * dth * dz * w / weight_sum[r.cell];  // N, the grain's share of the cell
        p.external_force[r.grain] -= f * Vec3(std::cos(th), std::sin(th), 0.0);
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
