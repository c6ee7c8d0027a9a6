// Residual layout, phase labelling and per-phase errors (see residuals.hpp).
#include "engine/diagnose/residuals.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "engine/diagnose/metrics.hpp"

namespace triax::diagnose {

namespace {

std::string kpa_tag(double confining_pa) {
    return "@" + std::to_string(static_cast<long>(std::lround(confining_pa / 1000.0))) + "kPa";
}

// Moving average over +-half readings: noise must not move the peak or the rate minimum.
std::vector<double> smoothed(const std::vector<double>& y, std::size_t half) {
    std::vector<double> s(y.size());
    for (std::size_t i = 0; i < y.size(); ++i) {
        const std::size_t a = i >= half ? i - half : 0, b = std::min(y.size() - 1, i + half);
        double sum = 0.0;
        for (std::size_t k = a; k <= b; ++k) sum += y[k];
        s[i] = sum / static_cast<double>(b - a + 1);
    }
    return s;
}

std::vector<std::string> split_at_extremum(const std::vector<double>& y, const char* before, const char* after) {
    const auto s = smoothed(y, 2);
    const std::size_t peak = static_cast<std::size_t>(std::max_element(s.begin(), s.end()) - s.begin());
    std::vector<std::string> phase(y.size());
    for (std::size_t i = 0; i < y.size(); ++i) phase[i] = i <= peak ? before : after;
    return phase;
}

std::vector<std::string> creep_phases(const std::vector<double>& t, const std::vector<double>& eps) {
    const std::size_t n = t.size();
    // The loading itself is the instant series; every reading here is after it.
    std::vector<std::string> phase(n, "primary");
    std::vector<std::size_t> timed;
    for (std::size_t i = 0; i < n; ++i) timed.push_back(i);
    if (timed.size() < 5) return phase;
    // Strain rate over a +-2 reading window (readings are often log-spaced in time).
    std::vector<double> rate(timed.size());
    for (std::size_t k = 0; k < timed.size(); ++k) {
        const std::size_t a = timed[k >= 2 ? k - 2 : 0], b = timed[std::min(timed.size() - 1, k + 2)];
        rate[k] = t[b] > t[a] ? (eps[b] - eps[a]) / (t[b] - t[a]) : 0.0;
    }
    const std::size_t kmin = static_cast<std::size_t>(std::min_element(rate.begin(), rate.end()) - rate.begin());
    const double floor_rate = std::max(rate[kmin], 0.0);
    const double band = 2.0 * floor_rate + 1e-15;
    for (std::size_t k = 0; k < timed.size(); ++k) {
        const char* p = "steady";
        if (k < kmin && rate[k] > band) p = "primary";
        else if (k > kmin && rate[k] > band) p = "tertiary";
        phase[timed[k]] = p;
    }
    // Tertiary only counts if it lasts to the end: a noisy blip in the steady part is not failure.
    bool tail = true;
    for (std::size_t k = timed.size(); k-- > kmin + 1;) {
        if (phase[timed[k]] != "tertiary") tail = false;
        else if (!tail) phase[timed[k]] = "steady";
    }
    return phase;
}

double range_of(const std::vector<double>& v) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (double x : v)
        if (std::isfinite(x)) lo = std::min(lo, x), hi = std::max(hi, x);
    return hi > lo ? hi - lo : 0.0;
}

// White reading noise of a creep series (departure of each reading from the line through
// its neighbours over log time), as noise_floor.cpp estimates it.
double creep_reading_noise(const std::vector<double>& t, const std::vector<double>& y) {
    double ss = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 1; i + 1 < t.size(); ++i) {
        const double x0 = std::log(std::max(t[i - 1], 1e-3)), x1 = std::log(std::max(t[i], 1e-3)),
                     x2 = std::log(std::max(t[i + 1], 1e-3));
        if (!(x2 > x0)) continue;
        const double w = (x2 - x1) / (x2 - x0);
        const double d = y[i] - (w * y[i - 1] + (1.0 - w) * y[i + 1]);
        ss += d * d / (1.0 + w * w + (1.0 - w) * (1.0 - w));
        ++n;
    }
    return n ? std::sqrt(ss / static_cast<double>(n)) : 0.0;
}

// A stage whose creep is within a few reading-noise SDs has no range to normalise by: its
// scale is at least kCreepNoiseScale x the readings' noise, so noise alone is not 50 % NRMSE.
constexpr double kCreepNoiseScale = 4.0;

// Keep only readings where both abscissa and ordinate are finite.
void push_series(std::vector<ResidualSeries>& out, ResidualSeries s, const std::vector<double>& x,
                 const std::vector<double>& y) {
    for (std::size_t i = 0; i < x.size() && i < y.size(); ++i)
        if (std::isfinite(x[i]) && std::isfinite(y[i])) s.x.push_back(x[i]), s.lab.push_back(y[i]);
    if (s.x.size() < 3) return;
    s.scale = range_of(s.lab);
    if (s.quantity == Quantity::CreepStrain || s.quantity == Quantity::CreepDeformation)
        s.scale = std::max(s.scale, kCreepNoiseScale * creep_reading_noise(s.x, s.lab));
    if (s.scale <= 0.0) s.scale = std::max(std::abs(s.lab.front()), 1e-12);
    if (s.quantity == Quantity::Deviator) s.phase = split_at_extremum(s.lab, "pre_peak", "post_peak");
    else if (s.quantity == Quantity::Volumetric) s.phase = split_at_extremum(s.lab, "contraction", "dilation");
    else s.phase = creep_phases(s.x, s.lab);
    out.push_back(std::move(s));
}

const LabCurve* matching_curve(const LabDataset& d, CurveKind kind, int stage, double confining_pa) {
    for (const auto& c : d.curves)
        if (c.kind == kind && (kind == CurveKind::Shear || c.stage == stage) &&
            same_confining(c.confining_pa, confining_pa))
            return &c;
    return nullptr;
}

const LabCurve* matching_curve(const LabDataset& d, const ResidualSeries& s) {
    const bool creep = s.quantity == Quantity::CreepStrain || s.quantity == Quantity::CreepDeformation;
    return matching_curve(d, creep ? CurveKind::Creep : CurveKind::Shear, s.stage, s.confining_pa);
}

// y(x) at xq, linear; xq before the first reading reads the first; NaN past the last.
double value_at(const std::vector<double>& x, const std::vector<double>& y, double xq) {
    if (x.empty() || x.size() != y.size()) return std::numeric_limits<double>::quiet_NaN();
    if (xq <= x.front()) return y.front();
    if (xq > x.back()) return std::numeric_limits<double>::quiet_NaN();
    const auto j = static_cast<std::size_t>(std::lower_bound(x.begin(), x.end(), xq) - x.begin());
    if (x[j] == x[j - 1]) return y[j];
    const double w = (xq - x[j - 1]) / (x[j] - x[j - 1]);
    return (1.0 - w) * y[j - 1] + w * y[j];
}

// One pressure's stages: the deformation at loading of each.
struct InstantReadings {
    double confining_pa = 0.0;
    bool as_strain = true;
    std::vector<double> stage, time, value;
};

}  // namespace

std::vector<ResidualSeries> residual_layout(const LabDataset& lab) {
    std::vector<ResidualSeries> out;
    std::vector<InstantReadings> instants;
    for (const auto& c : lab.curves) {
        const std::string tag = kpa_tag(c.confining_pa);
        if (c.kind == CurveKind::Shear) {
            if (c.axial_strain.empty()) continue;
            if (!c.deviator_pa.empty())
                push_series(out, {"stress_strain" + tag, "Pa", Quantity::Deviator, 0, c.confining_pa, 1.0, {}, {}, {}},
                            c.axial_strain, c.deviator_pa);
            if (!c.volumetric_strain.empty())
                push_series(out, {"volumetric" + tag, "-", Quantity::Volumetric, 0, c.confining_pa, 1.0, {}, {}, {}},
                            c.axial_strain, c.volumetric_strain);
        } else {
            if (c.time_s.empty()) continue;
            const bool as_strain = !c.axial_strain.empty();
            const std::vector<double>& y = as_strain ? c.axial_strain : c.axial_deformation_m;
            if (y.size() != c.time_s.size()) continue;
            // The stage's first finite reading: its deformation at loading; the creep counts from it.
            std::size_t first = 0;
            while (first < y.size() && !(std::isfinite(c.time_s[first]) && std::isfinite(y[first]))) ++first;
            if (first == y.size()) continue;
            auto it = std::find_if(instants.begin(), instants.end(), [&](const InstantReadings& r) {
                return r.as_strain == as_strain && same_confining(r.confining_pa, c.confining_pa);
            });
            if (it == instants.end()) it = instants.insert(instants.end(), InstantReadings{c.confining_pa, as_strain, {}, {}, {}});
            it->stage.push_back(static_cast<double>(c.stage));
            it->time.push_back(c.time_s[first]);
            it->value.push_back(y[first]);
            std::vector<double> t, rel;
            for (std::size_t i = first + 1; i < y.size(); ++i)
                if (c.time_s[i] > c.time_s[first]) t.push_back(c.time_s[i]), rel.push_back(y[i] - y[first]);
            ResidualSeries rs{"creep-" + std::to_string(c.stage) + tag, as_strain ? "-" : "m",
                              as_strain ? Quantity::CreepStrain : Quantity::CreepDeformation, c.stage, c.confining_pa,
                              1.0, {}, {}, {}};
            rs.reference_time = c.time_s[first];
            push_series(out, std::move(rs), t, rel);
        }
    }
    // A pressure's creep stages share one scale, the largest stage's creep range: a low-stress
    // stage's creep is small and mostly reading noise, and normalised by its own range it
    // would outweigh the stages that creep.
    for (auto& a : out) {
        if (a.quantity != Quantity::CreepStrain && a.quantity != Quantity::CreepDeformation) continue;
        for (const auto& b : out)
            if (b.quantity == a.quantity && same_confining(b.confining_pa, a.confining_pa))
                a.scale = std::max(a.scale, b.scale);
    }
    for (const auto& r : instants) {
        ResidualSeries s{"instant" + kpa_tag(r.confining_pa), r.as_strain ? "-" : "m", Quantity::CreepInstant, 0,
                         r.confining_pa, 1.0, r.stage, r.value, std::vector<std::string>(r.stage.size(), "instant")};
        s.stage_time = r.time;
        s.instant_as_strain = r.as_strain;
        // The range over the stages (the loading curve they sample); one stage: its value.
        s.scale = range_of(s.lab);
        for (double v : s.lab) s.scale = std::max(s.scale, s.lab.size() < 3 ? std::abs(v) : 0.0);
        if (s.scale <= 0.0) s.scale = 1e-12;
        out.push_back(std::move(s));
    }
    if (out.empty())
        throw std::invalid_argument(
            "lab dataset '" + lab.name +
            "' has no usable curve: a shear curve needs axial_strain with deviator or volumetric strain, "
            "a creep curve needs time and axial strain or deformation, each with at least 3 finite readings");
    return out;
}

std::vector<double> normalised_residual(const std::vector<ResidualSeries>& layout, const LabDataset& predicted,
                                        std::vector<std::vector<double>>* model_values) {
    std::vector<double> r;
    if (model_values) model_values->clear();
    for (const auto& s : layout) {
        std::vector<double> model(s.x.size(), std::numeric_limits<double>::quiet_NaN());
        if (s.quantity == Quantity::CreepInstant) {
            for (std::size_t i = 0; i < s.x.size(); ++i)
                if (const LabCurve* c = matching_curve(predicted, CurveKind::Creep, static_cast<int>(std::lround(s.x[i])),
                                                       s.confining_pa))
                    model[i] = value_at(c->time_s, s.instant_as_strain ? c->axial_strain : c->axial_deformation_m,
                                        s.stage_time[i]);
        } else if (const LabCurve* c = matching_curve(predicted, s)) {
            const bool creep = s.quantity == Quantity::CreepStrain || s.quantity == Quantity::CreepDeformation;
            const std::vector<double>& xm = creep ? c->time_s : c->axial_strain;
            const std::vector<double>& ym = s.quantity == Quantity::Deviator          ? c->deviator_pa
                                            : s.quantity == Quantity::Volumetric      ? c->volumetric_strain
                                            : s.quantity == Quantity::CreepDeformation ? c->axial_deformation_m
                                                                                      : c->axial_strain;
            // Creep: the model counted from its own value at the lab's first reading of the stage.
            const double origin = creep ? value_at(xm, ym, s.reference_time) : 0.0;
            if (!xm.empty() && xm.size() == ym.size() && std::isfinite(origin)) {
                const auto m = compare_curve(xm, ym, s.x, s.lab);
                // compare_curve keeps reading order and drops out-of-range readings; match by abscissa.
                std::size_t j = 0;
                for (std::size_t i = 0; i < s.x.size() && j < m.points.size(); ++i)
                    if (m.points[j].x == s.x[i] && m.points[j].lab == s.lab[i]) model[i] = m.points[j++].model - origin;
            }
        }
        for (std::size_t i = 0; i < s.x.size(); ++i)
            r.push_back(std::isfinite(model[i]) ? (model[i] - s.lab[i]) / s.scale : kUnreachedPenalty);
        if (model_values) model_values->push_back(std::move(model));
    }
    return r;
}

std::vector<std::pair<std::size_t, std::size_t>> series_ranges(const std::vector<ResidualSeries>& layout) {
    std::vector<std::pair<std::size_t, std::size_t>> ranges;
    std::size_t at = 0;
    for (const auto& s : layout) {
        ranges.emplace_back(at, at + s.x.size());
        at += s.x.size();
    }
    return ranges;
}

std::vector<PhaseError> phase_errors(const std::vector<ResidualSeries>& layout, const std::vector<double>& residual) {
    static const char* kOrder[] = {"pre_peak", "post_peak", "contraction", "dilation",
                                   "instant",  "primary",   "steady",      "tertiary"};
    std::vector<PhaseError> out;
    const auto ranges = series_ranges(layout);
    for (std::size_t k = 0; k < layout.size(); ++k) {
        const auto& s = layout[k];
        auto add = [&](const std::string& phase) {
            double ss = 0.0;
            std::size_t n = 0, unreached = 0;
            for (std::size_t i = 0; i < s.x.size(); ++i)
                if (phase == "all" || s.phase[i] == phase) {
                    const double r = residual[ranges[k].first + i];
                    if (is_unreached(r)) {
                        ++unreached;
                        continue;
                    }
                    ss += r * r;
                    ++n;
                }
            if (n + unreached == 0) return;
            const double nrmse = n ? std::sqrt(ss / static_cast<double>(n)) : 0.0;
            out.push_back({s.label, phase, s.unit, n, unreached, nrmse * s.scale, nrmse});
        };
        add("all");
        for (const char* p : kOrder) add(p);
    }
    return out;
}

}  // namespace triax::diagnose
