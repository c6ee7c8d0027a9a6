#include "server/io/ensemble_json.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace triax::io {

using diagnose::Band;
using diagnose::EnsembleSummary;
using nlohmann::json;

namespace {

json band_json(const Band& b, double scale) {
    auto scaled = [&](const std::vector<double>& v) {
        json a = json::array();
        for (double x : v) a.push_back(std::isfinite(x) ? json(x * scale) : json(nullptr));
        return a;
    };
    return {{"n", b.n}, {"mean", scaled(b.mean)}, {"std", scaled(b.std)}, {"min", scaled(b.min)}, {"max", scaled(b.max)}};
}

json point_json(const Band& b, double scale) {
    if (b.n.empty() || b.n[0] == 0) return nullptr;
    return {{"n", b.n[0]}, {"mean", b.mean[0] * scale}, {"std", b.std[0] * scale}, {"min", b.min[0] * scale}, {"max", b.max[0] * scale}};
}

std::string number(double v) {
    if (!std::isfinite(v)) return "";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

}  // namespace

json ensemble_to_json(const EnsembleSummary& s, bool with_curves) {
    json members = json::array();
    for (const auto& m : s.members) {
        json j{{"seed", m.seed}, {"ok", m.ok}};
        if (!m.ok) {
            j["error"] = m.error;
        } else {
            j["q_failure_kPa"] = m.q_failure_pa * 1e-3;
            j["axial_strain_at_failure_pct"] = m.axial_strain_at_failure * 100.0;
            json stages = json::array();
            for (const auto& st : m.stages)
                stages.push_back({{"stage", st.stage}, {"stress_level", st.stress_level}, {"accelerating", st.accelerating},
                                  {"converged", st.converged}, {"ruptured", st.ruptured}});
            j["creep_stages"] = stages;
        }
        members.push_back(j);
    }
    json stages = json::array();
    for (const auto& c : s.stages) {
        json j{{"stage", c.stage},
               {"stress_level_mean", c.stress_level_mean},
               {"seeds_reached", c.reached},
               {"share_accelerating", c.share_accelerating},
               {"share_converged", c.share_converged},
               {"share_unsettled", c.share_unsettled},
               {"share_ruptured", c.share_ruptured}};
        if (with_curves) {
            json t = json::array();
            for (double x : c.time_s) t.push_back(x / 60.0);
            j["time_min"] = t;
            j["axial_strain_pct"] = band_json(c.axial_strain, 100.0);
        }
        stages.push_back(j);
    }
    json out{{"scheme_name", s.scheme_name},
             {"seeds", s.members.size()},
             {"seeds_ok", s.ok},
             {"q_failure_kPa", point_json(s.q_failure_pa, 1e-3)},
             {"axial_strain_at_failure_pct", point_json(s.axial_strain_at_failure, 100.0)},
             {"creep_stages", stages},
             {"members", members}};
    if (with_curves) {
        json e = json::array();
        for (double x : s.shear_axial_strain) e.push_back(x * 100.0);
        out["shear"] = {{"axial_strain_pct", e},
                        {"q_kPa", band_json(s.deviator_pa, 1e-3)},
                        {"volumetric_strain_pct", band_json(s.volumetric_strain, 100.0)}};
    }
    return out;
}

std::string shear_band_csv(const EnsembleSummary& s) {
    std::ostringstream o;
    o << "axial_strain_pct,n_seeds,q_mean_kPa,q_std_kPa,q_min_kPa,q_max_kPa,volumetric_strain_mean_pct,"
         "volumetric_strain_std_pct,volumetric_strain_min_pct,volumetric_strain_max_pct\n";
    for (std::size_t i = 0; i < s.shear_axial_strain.size(); ++i) {
        const auto& q = s.deviator_pa;
        const auto& v = s.volumetric_strain;
        o << number(s.shear_axial_strain[i] * 100.0) << ',' << q.n[i] << ',' << number(q.mean[i] * 1e-3) << ','
          << number(q.std[i] * 1e-3) << ',' << number(q.min[i] * 1e-3) << ',' << number(q.max[i] * 1e-3) << ','
          << number(v.mean[i] * 100.0) << ',' << number(v.std[i] * 100.0) << ',' << number(v.min[i] * 100.0) << ','
          << number(v.max[i] * 100.0) << '\n';
    }
    return o.str();
}

std::string creep_band_csv(const EnsembleSummary& s) {
    std::ostringstream o;
    o << "stage,time_min,n_seeds,axial_strain_mean_pct,axial_strain_std_pct,axial_strain_min_pct,axial_strain_max_pct\n";
    for (const auto& c : s.stages)
        for (std::size_t i = 0; i < c.time_s.size(); ++i) {
            const auto& a = c.axial_strain;
            o << c.stage << ',' << number(c.time_s[i] / 60.0) << ',' << a.n[i] << ',' << number(a.mean[i] * 100.0) << ','
              << number(a.std[i] * 100.0) << ',' << number(a.min[i] * 100.0) << ',' << number(a.max[i] * 100.0) << '\n';
        }
    return o.str();
}

}  // namespace triax::io
