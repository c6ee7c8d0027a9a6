#include "server/runs/series.hpp"

#include <cmath>
#include <sstream>

namespace triax::service {

using nlohmann::json;

const std::vector<SeriesSpec>& series_specs() {
    static const std::vector<SeriesSpec> specs = {
        {"stress_strain", "shear", {"axial_strain_pct", "q_kPa", "p_kPa", "sigma1_kPa", "sigma3_kPa"}},
        {"volumetric", "shear", {"axial_strain_pct", "volumetric_strain_pct"}},
        {"creep", "creep", {"stage", "time_min", "axial_deformation_mm", "axial_strain_pct"}},
        {"energies",
         "energy",
         {"phase_index", "step", "time_min", "strain_J", "slip_J", "damping_J", "kinetic_J", "bond_J",
          "boundary_work_J", "creep_J", "breakage_J"}},
        {"measurements",
         "measurement",
         {"sphere", "step", "time_min", "z_displacement_mm", "rotation_rate_x_rad_s", "rotation_rate_y_rad_s",
          "rotation_rate_z_rad_s", "porosity", "coordination"}},
    };
    return specs;
}

const SeriesSpec* find_series(const std::string& name) {
    for (const auto& s : series_specs())
        if (name == s.name) return &s;
    return nullptr;
}

json rows_from_events(const SeriesSpec& spec, const std::vector<json>& event_data) {
    json rows = json::array();
    for (const auto& d : event_data) {
        json r = json::array();
        for (const auto& c : spec.columns) r.push_back(d.contains(c) ? d[c] : json(nullptr));
        rows.push_back(std::move(r));
    }
    return rows;
}

json filter_series(const SeriesSpec& spec, json rows, const SeriesQuery& q) {
    const bool staged = !spec.columns.empty() && spec.columns.front() == "stage";
    const std::size_t xcol = staged ? 1 : 0;
    json kept = json::array();
    for (auto& r : rows) {
        if (staged && q.stage && !(r[0].is_number() && r[0].get<int>() == *q.stage)) continue;
        if (q.from || q.to) {
            if (!r[xcol].is_number()) continue;
            const double x = r[xcol].get<double>();
            if ((q.from && x < *q.from) || (q.to && x > *q.to)) continue;
        }
        kept.push_back(std::move(r));
    }
    if (q.max_points && kept.size() > *q.max_points) {
        // Uniform in index: rows i = round(k (n-1)/(m-1)), so the first and last survive.
        const std::size_t n = kept.size(), m = std::max<std::size_t>(*q.max_points, 2);
        json thin = json::array();
        std::size_t prev = n;
        for (std::size_t k = 0; k < m; ++k) {
            const auto i = static_cast<std::size_t>(std::llround(static_cast<double>(k) * (n - 1) / (m - 1)));
            if (i != prev) thin.push_back(kept[i]);
            prev = i;
        }
        if (*q.max_points == 1) thin = json::array({kept.front()});
        kept = std::move(thin);
    }
    return kept;
}

std::string series_csv(const std::vector<std::string>& columns, const json& rows) {
    std::ostringstream os;
    os.precision(10);
    for (std::size_t i = 0; i < columns.size(); ++i) os << (i ? "," : "") << columns[i];
    os << '\n';
    for (const auto& r : rows) {
        for (std::size_t i = 0; i < r.size(); ++i) {
            if (i) os << ',';
            if (r[i].is_number()) os << r[i].get<double>();
            else if (r[i].is_boolean()) os << (r[i].get<bool>() ? 1 : 0);
        }
        os << '\n';
    }
    return os.str();
}

}  // namespace triax::service
