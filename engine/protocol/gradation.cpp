#include "engine/protocol/gradation.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/core/types.hpp"

namespace triax::protocol {

std::vector<SizeClass> size_classes(const GradationSpec& g) {
    std::vector<SizeClass> out;
    if (g.kind == GradationSpec::Kind::RadiusRatio) {
        if (!(g.r_min_m > 0.0)) throw InputError("gradation.r_min_m: must be > 0");
        if (!(g.radius_ratio >= 1.0)) throw InputError("gradation.radius_ratio: must be >= 1");
        out.push_back({g.r_min_m, g.r_min_m * g.radius_ratio, 1.0});
        return out;
    }
    const auto& c = g.sieve_curve;
    if (c.size() < 2) throw InputError("gradation.sieve_curve: needs at least 2 points");
    for (std::size_t i = 0; i < c.size(); ++i) {
        const std::string at = "gradation.sieve_curve[" + std::to_string(i) + "]";
        if (!(c[i].size_m > 0.0)) throw InputError(at + ".size: must be > 0");
        if (c[i].passing_pct < 0.0 || c[i].passing_pct > 100.0) throw InputError(at + ".passing: must be in [0, 100]");
        if (i > 0 && !(c[i].size_m > c[i - 1].size_m)) throw InputError(at + ".size: sizes must increase");
        if (i > 0 && c[i].passing_pct < c[i - 1].passing_pct) throw InputError(at + ".passing: must not decrease");
    }
    const double total = c.back().passing_pct - c.front().passing_pct;
    if (!(total > 0.0)) throw InputError("gradation.sieve_curve: passing must rise between first and last point");
    // Fines: mass between the first sieve and the cut-off, lumped at the weighted mean radius.
    double fines_mass = 0.0, fines_rm = 0.0;
    for (std::size_t i = 1; i < c.size(); ++i) {
        const double m = (c[i].passing_pct - c[i - 1].passing_pct) / total;
        if (m <= 0.0) continue;
        const double r_lo = 0.5 * c[i - 1].size_m, r_hi = 0.5 * c[i].size_m;
        if (c[i].size_m <= g.fines_cutoff_m) {
            fines_mass += m;
            fines_rm += m * 0.5 * (r_lo + r_hi);  // R_i M_i of Eq. 2, R_i the class mean radius
        } else {
            out.push_back({r_lo, r_hi, m});
        }
    }
    if (fines_mass > 0.0) {
        const double r = fines_rm / fines_mass;
        out.insert(out.begin(), {r, r, fines_mass});
    }
    return out;
}

double weighted_fines_radius_m(const GradationSpec& g) {
    if (g.kind != GradationSpec::Kind::SieveCurve) return 0.0;
    const auto cls = size_classes(g);
    if (!cls.empty() && cls.front().r_lo_m == cls.front().r_hi_m && cls.front().r_hi_m * 2.0 <= g.fines_cutoff_m)
        return cls.front().r_lo_m;
    return 0.0;
}

double gradation_r_min_m(const GradationSpec& g) {
    const auto cls = size_classes(g);
    double r = cls.front().r_lo_m;
    for (const auto& k : cls) r = std::min(r, k.r_lo_m);
    return r;
}

double gradation_r_max_m(const GradationSpec& g) {
    const auto cls = size_classes(g);
    double r = 0.0;
    for (const auto& k : cls) r = std::max(r, k.r_hi_m);
    return r;
}

std::vector<double> draw_radii(const GradationSpec& g, double solid_volume_m3, std::mt19937_64& rng) {
    const auto cls = size_classes(g);
    constexpr double kPi = 3.14159265358979323846;
    std::vector<double> radii;
    std::uniform_real_distribution<double> u(0.0, 1.0);
    if (g.kind == GradationSpec::Kind::RadiusRatio) {
        // Uniform by number (PFC convention): keep drawing until the volume is reached.
        double v = 0.0;
        while (v < solid_volume_m3) {
            const double r = cls[0].r_lo_m + u(rng) * (cls[0].r_hi_m - cls[0].r_lo_m);
            radii.push_back(r);
            v += 4.0 / 3.0 * kPi * r * r * r;
        }
    } else {
        // Each class receives its mass share of the solid volume.
        for (const auto& k : cls) {
            const double target = k.mass_fraction * solid_volume_m3;
            double v = 0.0;
            while (v < target) {
                const double r = k.r_lo_m + u(rng) * (k.r_hi_m - k.r_lo_m);
                radii.push_back(r);
                v += 4.0 / 3.0 * kPi * r * r * r;
            }
        }
    }
    // Largest first: placing big grains first packs them without overlap trouble.
    std::sort(radii.begin(), radii.end(), std::greater<double>());
    return radii;
}

}  // namespace triax::protocol
