#include "server/scaleout/ensemble.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "engine/protocol/run_observer.hpp"
#include "engine/protocol/triaxial_test.hpp"
#include "server/scaleout/wire_format.hpp"

namespace triax::scaleout {

using nlohmann::json;

std::vector<std::uint64_t> parse_seed_list(std::string_view text) {
    std::vector<std::uint64_t> out;
    auto number = [&](std::string_view s) -> std::uint64_t {
        if (s.empty() || s.find_first_not_of("0123456789") != std::string_view::npos || s.size() > 18)
            throw std::invalid_argument("--seeds: '" + std::string(s) + "' is not a seed (a number >= 0)");
        return std::stoull(std::string(s));
    };
    std::size_t at = 0;
    while (at <= text.size()) {
        const auto comma = std::min(text.find(',', at), text.size());
        const auto part = text.substr(at, comma - at);
        const auto dash = part.find('-');
        const std::uint64_t lo = number(part.substr(0, dash));
        const std::uint64_t hi = dash == std::string_view::npos ? lo : number(part.substr(dash + 1));
        if (hi < lo) throw std::invalid_argument("--seeds: range '" + std::string(part) + "' runs backwards");
        if (hi - lo >= 10000 || out.size() + (hi - lo) >= 10000) throw std::invalid_argument("--seeds: more than 10000 seeds");
        for (std::uint64_t s = lo; s <= hi; ++s) out.push_back(s);
        at = comma + 1;
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

std::string member_task(std::uint64_t seed) {
    WireWriter w;
    w.u64(seed);
    return w.take();
}

namespace {

// A member's result bytes: q_f, strain at failure, the shear curve, then per creep stage
// its number, stress level, regime flags and translated curve.
std::string encode_member(const protocol::TestResult& r, std::uint64_t seed) {
    if (r.shear.empty()) throw std::runtime_error("the run did not shear (seed " + std::to_string(seed) + ")");
    WireWriter w;
    w.f64(r.q_failure_pa);
    w.f64(r.axial_strain_at_failure);
    std::vector<double> e, q, v;
    for (const auto& p : r.shear) e.push_back(p.axial_strain), q.push_back(p.q_pa), v.push_back(p.volumetric_strain);
    w.doubles(e);
    w.doubles(q);
    w.doubles(v);
    w.u64(r.creep_stages.size());
    for (const auto& st : r.creep_stages) {
        w.u64(static_cast<std::uint64_t>(st.stage));
        w.f64(st.stress_level);
        w.u64((st.accelerating ? 1u : 0u) | (st.converged ? 2u : 0u) | (st.ruptured ? 4u : 0u));
        std::vector<double> t, a;
        for (const auto& p : st.translated) t.push_back(p.time_s), a.push_back(p.axial_strain);
        w.doubles(t);
        w.doubles(a);
    }
    return w.take();
}

// Passes the caller's cancel poll to the engine; ignores everything else.
class CancelPoll final : public protocol::RunObserver {
public:
    explicit CancelPoll(const std::function<bool()>& poll) : poll_(poll) {}
    bool cancel_requested() override { return poll_(); }

private:
    const std::function<bool()>& poll_;
};

}  // namespace

TaskHandler member_handler(const protocol::TestScheme& scheme) {
    return [scheme](std::string_view task) {
        WireReader rd(task);
        protocol::TestScheme s = scheme;
        s.seed = rd.u64("seed");
        return encode_member(protocol::run_triaxial_test(s), s.seed);
    };
}

TaskHandler member_handler(const protocol::TestScheme& scheme, std::function<bool()> cancel_requested) {
    return [scheme, cancel = std::move(cancel_requested)](std::string_view task) {
        WireReader rd(task);
        protocol::TestScheme s = scheme;
        s.seed = rd.u64("seed");
        if (cancel()) throw MemberCancelled();
        CancelPoll observer(cancel);
        const auto r = protocol::run_triaxial_test(s, observer);
        if (r.cancelled) throw MemberCancelled();
        return encode_member(r, s.seed);
    };
}

EnsembleMember member_from_result(std::uint64_t seed, const TaskResult& result) {
    EnsembleMember m;
    m.seed = seed;
    if (!result.ok) {
        m.error = result.bytes;
        return m;
    }
    try {
        WireReader rd(result.bytes);
        m.q_failure_pa = rd.f64("q_f");
        m.axial_strain_at_failure = rd.f64("strain at failure");
        m.axial_strain = rd.doubles("axial strain");
        m.deviator_pa = rd.doubles("deviator");
        m.volumetric_strain = rd.doubles("volumetric strain");
        const auto n = rd.u64("creep stages");
        for (std::uint64_t k = 0; k < n && k < 1000; ++k) {
            MemberStage st;
            st.stage = static_cast<int>(rd.u64("stage"));
            st.stress_level = rd.f64("stress level");
            const auto flags = rd.u64("regime");
            st.accelerating = flags & 1u, st.converged = flags & 2u, st.ruptured = flags & 4u;
            st.time_s = rd.doubles("creep time");
            st.axial_strain = rd.doubles("creep strain");
            m.stages.push_back(std::move(st));
        }
        if (!rd.done()) throw std::runtime_error("wire format: bytes left after the member");
        m.ok = true;
    } catch (const std::exception& e) {
        m = EnsembleMember{};
        m.seed = seed;
        m.error = e.what();
    }
    return m;
}

namespace {

// y(x) on a curve with ascending-ish x (shear strain can step back a little at a platen
// reversal: the first bracketing segment is used); nullopt beyond the curve's last x.
bool interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x, double& y) {
    if (xs.empty() || x > xs.back() + 1e-15 || x < xs.front() - 1e-15) return false;
    for (std::size_t i = 1; i < xs.size(); ++i)
        if (xs[i] >= x) {
            const double dx = xs[i] - xs[i - 1];
            const double f = dx > 0.0 ? std::clamp((x - xs[i - 1]) / dx, 0.0, 1.0) : 1.0;
            y = ys[i - 1] + f * (ys[i] - ys[i - 1]);
            return true;
        }
    y = ys.back();
    return true;
}

void add_point(Band& b, const std::vector<double>& values) {
    b.n.push_back(static_cast<int>(values.size()));
    if (values.empty()) {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        b.mean.push_back(nan), b.std.push_back(nan), b.min.push_back(nan), b.max.push_back(nan);
        return;
    }
    double sum = 0.0;
    for (double v : values) sum += v;
    const double mean = sum / static_cast<double>(values.size());
    double ss = 0.0;
    for (double v : values) ss += (v - mean) * (v - mean);
    b.mean.push_back(mean);
    // Sample standard deviation (n - 1): the scatter of a packing, estimated from n seeds.
    b.std.push_back(values.size() > 1 ? std::sqrt(ss / static_cast<double>(values.size() - 1)) : 0.0);
    b.min.push_back(*std::min_element(values.begin(), values.end()));
    b.max.push_back(*std::max_element(values.begin(), values.end()));
}

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
                double y = 0.0;
                // The isotropic start (0, 0, 0) precedes the first recorded shear point.
                std::vector<double> xs = m->axial_strain, qs = m->deviator_pa, vs = m->volumetric_strain;
                if (!xs.empty() && xs.front() > 0.0) xs.insert(xs.begin(), 0.0), qs.insert(qs.begin(), 0.0), vs.insert(vs.begin(), 0.0);
                if (interpolate(xs, qs, x, y)) q.push_back(y);
                if (interpolate(xs, vs, x, y)) v.push_back(y);
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
            for (const auto* st : list) {
                double y = 0.0;
                if (interpolate(st->time_s, st->axial_strain, t, y)) a.push_back(y);
            }
            add_point(c.axial_strain, a);
        }
        s.stages.push_back(std::move(c));
    }
    return s;
}

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

}  // namespace triax::scaleout
