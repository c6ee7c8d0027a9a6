#include "engine/diagnose/packing_ensemble.hpp"

#include <algorithm>
#include <cmath>

#include "engine/diagnose/curve_statistics.hpp"

namespace triax::diagnose {

namespace {

bool same_curve(const LabCurve& a, const LabCurve& b) {
    return a.kind == b.kind && a.stage == b.stage &&
           std::abs(a.confining_pa - b.confining_pa) <= 1e-6 * std::max(1.0, std::abs(a.confining_pa));
}

// The abscissa a curve is read along: time for creep, axial strain for shear.
const std::vector<double>& abscissa(const LabCurve& c) {
    return c.kind == CurveKind::Creep ? c.time_s : c.axial_strain;
}

// Mean of `series(c)` of every member along `grid`; an empty series in a member leaves the
// mean's series empty.
template <class Series>
std::vector<double> mean_series(const std::vector<const LabCurve*>& members, const std::vector<double>& grid,
                                Series series) {
    for (const LabCurve* c : members)
        if (series(*c).size() != abscissa(*c).size() || series(*c).empty()) return {};
    std::vector<double> out(grid.size()), values(members.size());
    for (std::size_t i = 0; i < grid.size(); ++i) {
        for (std::size_t k = 0; k < members.size(); ++k)
            values[k] = value_at_clamped(abscissa(*members[k]), series(*members[k]), grid[i]);
        out[i] = spread_of(values).mean;
    }
    return out;
}

}  // namespace

LabDataset mean_over_packings(const std::vector<LabDataset>& packings) {
    if (packings.empty()) return {};
    if (packings.size() == 1) return packings.front();
    LabDataset out;
    out.name = packings.front().name;
    // Every curve of any packing, in the order they first appear.
    std::vector<const LabCurve*> keys;
    for (const auto& p : packings)
        for (const auto& c : p.curves)
            if (std::none_of(keys.begin(), keys.end(), [&](const LabCurve* k) { return same_curve(*k, c); }))
                keys.push_back(&c);
    for (const LabCurve* key : keys) {
        std::vector<const LabCurve*> members;
        for (const auto& p : packings)
            for (const auto& c : p.curves)
                if (same_curve(c, *key) && !abscissa(c).empty()) {
                    members.push_back(&c);
                    break;
                }
        if (members.empty()) continue;
        double end = abscissa(*members.front()).back();
        for (const LabCurve* c : members) end = std::min(end, abscissa(*c).back());
        LabCurve m;
        m.kind = key->kind;
        m.stage = key->stage;
        m.confining_pa = key->confining_pa;
        m.stress_level = key->stress_level;
        std::vector<double> grid;
        for (double x : abscissa(*members.front()))
            if (x <= end) grid.push_back(x);
        if (m.kind == CurveKind::Creep) m.time_s = grid;
        else m.axial_strain = grid;
        if (m.kind == CurveKind::Creep)
            m.axial_strain = mean_series(members, grid, [](const LabCurve& c) -> const auto& { return c.axial_strain; });
        m.axial_deformation_m =
            mean_series(members, grid, [](const LabCurve& c) -> const auto& { return c.axial_deformation_m; });
        m.deviator_pa = mean_series(members, grid, [](const LabCurve& c) -> const auto& { return c.deviator_pa; });
        m.volumetric_strain =
            mean_series(members, grid, [](const LabCurve& c) -> const auto& { return c.volumetric_strain; });
        out.curves.push_back(std::move(m));
    }
    return out;
}

}  // namespace triax::diagnose
