#include "engine/diagnose/seed_ensemble.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "engine/diagnose/curve_statistics.hpp"

namespace triax::diagnose {

namespace {

// One grid point of a band: the spread of the members that reach it (the toolkit's).
void add_point(Band& b, const std::vector<double>& values) {
    const auto sp = spread_of(values);
    b.n.push_back(sp.n);
    b.mean.push_back(sp.mean);
    b.std.push_back(sp.std());
    b.min.push_back(sp.min);
    b.max.push_back(sp.max);
}

}  // namespace

EnsembleSummary summarise_ensemble(std::string scheme_name, std::vector<EnsembleMember> members) {
    std::sort(members.begin(), members.end(), [](const auto& a, const auto& b) { return a.seed < b.seed; });
    EnsembleSummary s;
    s.scheme_name = std::move(scheme_name);
    s.members = std::move(members);
    std::vector<const EnsembleMember*> ok;
    for (const auto& m : s.members)
        if (m.ok) ok.push_back(&m);
    s.ok = static_cast<int>(ok.size());

    std::vector<double> qf, ef;
    double e_max = 0.0;
    for (const auto* m : ok) {
        qf.push_back(m->q_failure_pa);
        ef.push_back(m->axial_strain_at_failure);
        if (!m->axial_strain.empty()) e_max = std::max(e_max, m->axial_strain.back());
    }
    add_point(s.q_failure_pa, qf);
    add_point(s.axial_strain_at_failure, ef);
    constexpr int kGrid = 100;
    if (!ok.empty()) {
        for (int i = 0; i <= kGrid; ++i) {
            const double x = e_max * i / kGrid;
            s.shear_axial_strain.push_back(x);
            std::vector<double> q, v;
            for (const auto* m : ok) {
                // The isotropic start (0, 0, 0) precedes the first recorded shear point.
                std::vector<double> xs = m->axial_strain, qs = m->deviator_pa, vs = m->volumetric_strain;
                if (!xs.empty() && xs.front() > 0.0) xs.insert(xs.begin(), 0.0), qs.insert(qs.begin(), 0.0), vs.insert(vs.begin(), 0.0);
                if (const auto y = value_at(xs, qs, x)) q.push_back(*y);
                if (const auto y = value_at(xs, vs, x)) v.push_back(*y);
            }
            add_point(s.deviator_pa, q);
            add_point(s.volumetric_strain, v);
        }
    }

    std::map<int, std::vector<const MemberStage*>> by_stage;
    for (const auto* m : ok)
        for (const auto& st : m->stages) by_stage[st.stage].push_back(&st);
    for (const auto& [stage, list] : by_stage) {
        CreepStageSummary c;
        c.stage = stage;
        c.reached = static_cast<int>(list.size());
        double t_first = std::numeric_limits<double>::infinity(), t_max = 0.0, sl = 0.0;
        int acc = 0, conv = 0, rup = 0;
        for (const auto* st : list) {
            sl += st->stress_level;
            acc += st->accelerating, conv += st->converged, rup += st->ruptured;
            for (double t : st->time_s)
                if (t > 0.0) t_first = std::min(t_first, t);
            if (!st->time_s.empty()) t_max = std::max(t_max, st->time_s.back());
        }
        const double n = static_cast<double>(list.size());
        c.stress_level_mean = sl / n;
        c.share_accelerating = acc / n;
        c.share_converged = conv / n;
        c.share_unsettled = (n - acc - conv) / n;
        c.share_ruptured = rup / n;
        c.time_s.push_back(0.0);
        if (std::isfinite(t_first) && t_max > t_first)
            for (int i = 0; i < kGrid; ++i) c.time_s.push_back(t_first * std::pow(t_max / t_first, static_cast<double>(i) / (kGrid - 1)));
        for (double t : c.time_s) {
            std::vector<double> a;
            for (const auto* st : list)
                if (const auto y = value_at(st->time_s, st->axial_strain, t)) a.push_back(*y);
            add_point(c.axial_strain, a);
        }
        s.stages.push_back(std::move(c));
    }
    return s;
}

}  // namespace triax::diagnose
