#include "engine/protocol/imported_packing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <unordered_map>

#include "engine/protocol/test_scheme.hpp"

namespace triax::protocol {

namespace {

std::string where(const ImportedPacking& p, std::size_t q) {
    const std::string src = p.source.empty() ? "packing" : p.source;
    if (q < p.line.size() && p.line[q] > 0) return src + " line " + std::to_string(p.line[q]);
    return src + " grain " + std::to_string(q + 1);
}

std::string pct(double x) {
    char b[32];
    std::snprintf(b, sizeof b, "%.3g %%", 100.0 * x);
    return b;
}

std::string mm(double x) {
    char b[32];
    std::snprintf(b, sizeof b, "%.6g mm", 1e3 * x);
    return b;
}

}  // namespace

void validate_packing(const ImportedPacking& p, const TestScheme& scheme, const PackingTolerance& tol) {
    const std::size_t n = p.size();
    if (n == 0) throw InputError((p.source.empty() ? std::string("packing") : p.source) + ": no grains");
    if (p.radius.size() != n) throw InputError("packing: " + std::to_string(n) + " positions but " +
                                               std::to_string(p.radius.size()) + " radii");
    if ((!p.mass.empty() && p.mass.size() != n) || (!p.inertia.empty() && p.inertia.size() != n))
        throw InputError("packing: " + std::to_string(n) + " grains but " + std::to_string(p.mass.size()) + " masses and " +
                         std::to_string(p.inertia.size()) + " moments of inertia (give both for every grain, or neither)");
    const double R = 0.5 * scheme.specimen.diameter_m, H = scheme.specimen.height_m;
    const double R_out = (1.0 + tol.extent) * R, Z_out = (1.0 + tol.extent) * 0.5 * H;
    double r_max = 0.0;
    for (std::size_t q = 0; q < n; ++q) {
        const Vec3& x = p.position[q];
        const double r = p.radius[q];
        if (!std::isfinite(r) || r <= 0.0) throw InputError(where(p, q) + ": radius must be positive and finite");
        if (!x.allFinite()) throw InputError(where(p, q) + ": position is not a finite number");
        if (q < p.mass.size() && !(std::isfinite(p.mass[q]) && p.mass[q] > 0.0))
            throw InputError(where(p, q) + ": mass_kg must be positive and finite");
        if (q < p.inertia.size() && !(std::isfinite(p.inertia[q]) && p.inertia[q] > 0.0))
            throw InputError(where(p, q) + ": inertia_kg_m2 must be positive and finite");
        // The packing's own extent is the specimen (packing_extent); the scheme's only
        // bounds it, by the deformation a test can give it.
        const double rho = std::hypot(x.x(), x.y());
        if (rho + r > R_out)
            throw InputError(where(p, q) + ": grain outside the specimen: it reaches radius " + mm(rho + r) +
                             ", more than " + pct(tol.extent) + " beyond the specimen radius " + mm(R) +
                             " (specimen.diameter_mm; axis z through the origin)");
        if (x.z() - r < -Z_out || x.z() + r > Z_out)
            throw InputError(where(p, q) + ": grain outside the specimen: z from " + mm(x.z() - r) + " to " +
                             mm(x.z() + r) + " leaves [" + mm(-Z_out) + ", " + mm(Z_out) + "], the height " + mm(H) +
                             " + " + pct(tol.extent) + " (specimen.height_mm; centred at the origin)");
        r_max = std::max(r_max, r);
    }
    const std::string src = p.source.empty() ? std::string("packing") : p.source;
    if (!p.platen_z_m.empty()) {
        if (p.platen_z_m.size() != 2 || !std::isfinite(p.platen_z_m[0]) || !std::isfinite(p.platen_z_m[1]) ||
            !(p.platen_z_m[0] < p.platen_z_m[1]) || p.platen_z_m[0] < -Z_out || p.platen_z_m[1] > Z_out)
            throw InputError(src + ": the platens' heights must be two finite numbers, bottom below top, within [" +
                             mm(-Z_out) + ", " + mm(Z_out) + "]");
    }
    // Pairs through a uniform grid of cells 2 r_max wide: each grain meets the 27 cells around it.
    const double cell = 2.0 * r_max;
    auto key = [](long a, long b, long c) {
        return (static_cast<std::uint64_t>(a & 0x1FFFFF) << 42) | (static_cast<std::uint64_t>(b & 0x1FFFFF) << 21) |
               static_cast<std::uint64_t>(c & 0x1FFFFF);
    };
    auto idx = [&](double v) { return static_cast<long>(std::floor(v / cell)); };
    std::unordered_map<std::uint64_t, std::vector<std::size_t>> grid;
    for (std::size_t q = 0; q < n; ++q)
        grid[key(idx(p.position[q].x()), idx(p.position[q].y()), idx(p.position[q].z()))].push_back(q);
    for (std::size_t q = 0; q < n; ++q) {
        const long cx = idx(p.position[q].x()), cy = idx(p.position[q].y()), cz = idx(p.position[q].z());
        for (long a = cx - 1; a <= cx + 1; ++a)
            for (long b = cy - 1; b <= cy + 1; ++b)
                for (long c = cz - 1; c <= cz + 1; ++c) {
                    auto it = grid.find(key(a, b, c));
                    if (it == grid.end()) continue;
                    for (std::size_t o : it->second) {
                        if (o >= q) continue;
                        const double r_small = std::min(p.radius[q], p.radius[o]);
                        const double overlap = p.radius[q] + p.radius[o] - (p.position[q] - p.position[o]).norm();
                        if (overlap > tol.overlap * r_small)
                            throw InputError(where(p, q) + ": grain overlaps the grain of " + where(p, o) + " by " +
                                             pct(overlap / r_small) + " of the smaller radius (tolerance " +
                                             pct(tol.overlap) + ")");
                    }
                }
    }
    // A specimen much smaller than the scheme's: metres read as millimetres, or the wrong scheme.
    const PackingExtent e = packing_extent(p);
    if (e.height_m() < (1.0 - tol.extent) * H)
        throw InputError(src + ": the grains span " + mm(e.height_m()) + " in z, less than " + pct(1.0 - tol.extent) +
                         " of the specimen height " + mm(H) + " (specimen.height_mm; is the unit right?)");
    if (e.radius_m < (1.0 - tol.extent) * R)
        throw InputError(src + ": the grains span a diameter of " + mm(2.0 * e.radius_m) + ", less than " +
                         pct(1.0 - tol.extent) + " of the specimen diameter " + mm(2.0 * R) +
                         " (specimen.diameter_mm; is the unit right?)");
}

PackingExtent packing_extent(const ImportedPacking& p) {
    PackingExtent e;
    double reach = 0.0, lo = 1e300, hi = -1e300;
    for (std::size_t q = 0; q < p.size(); ++q) {
        const Vec3& x = p.position[q];
        reach = std::max(reach, std::hypot(x.x(), x.y()) + p.radius[q]);
        lo = std::min(lo, x.z() - p.radius[q]);
        hi = std::max(hi, x.z() + p.radius[q]);
    }
    const bool named = p.platen_z_m.size() == 2;
    e.bottom_z_m = named ? p.platen_z_m[0] : lo;
    e.top_z_m = named ? p.platen_z_m[1] : hi;
    e.radius_m = reach;
    return e;
}

}  // namespace triax::protocol
