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
    std::vector<std::string> phase(n, "primary");
    std::vector<std::size_t> timed;
    for (std::size_t i = 0; i < n; ++i) {
        if (t[i] <= 60.0) phase[i] = "instant";
        else timed.push_back(i);
    }
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

// Keep only readings where both abscissa and ordinate are finite.
void push_series(std::vector<ResidualSeries>& out, ResidualSeries s, const std::vector<double>& x,
                 const std::vector<double>& y) {
    for (std::size_t i = 0; i < x.size() && i < y.size(); ++i)
        if (std::isfinite(x[i]) && std::isfinite(y[i])) s.x.push_back(x[i]), s.lab.push_back(y[i]);
    if (s.x.size() < 3) return;
    s.scale = range_of(s.lab);
    if (s.scale <= 0.0) s.scale = std::max(std::abs(s.lab.front()), 1e-12);
    if (s.quantity == Quantity::Deviator) s.phase = split_at_extremum(s.lab, "pre_peak", "post_peak");
    else if (s.quantity == Quantity::Volumetric) s.phase = split_at_extremum(s.lab, "contraction", "dilation");
    else s.phase = creep_phases(s.x, s.lab);
    out.push_back(std::move(s));
}

const LabCurve* matching_curve(const LabDataset& d, const ResidualSeries& s) {
    const bool creep = s.quantity == Quantity::CreepStrain || s.quantity == Quantity::CreepDeformation;
    const CurveKind kind = creep ? CurveKind::Creep : CurveKind::Shear;
    for (const auto& c : d.curves)
        if (c.kind == kind && (kind == CurveKind::Shear || c.stage == s.stage) &&
            std::abs(c.confining_pa - s.confining_pa) <= 0.02 * std::max(s.confining_pa, 1.0))
            return &c;
    return nullptr;
}

}  // namespace

std::vector<ResidualSeries> residual_layout(const LabDataset& lab) {
    std::vector<ResidualSeries> out;
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
            const std::string label = "creep-" + std::to_string(c.stage) + tag;
            if (!c.axial_strain.empty())
                push_series(out, {label, "-", Quantity::CreepStrain, c.stage, c.confining_pa, 1.0, {}, {}, {}}, c.time_s,
                            c.axial_strain);
            else if (!c.axial_deformation_m.empty())
                push_series(out, {label, "m", Quantity::CreepDeformation, c.stage, c.confining_pa, 1.0, {}, {}, {}},
                            c.time_s, c.axial_deformation_m);
        }
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
        if (const LabCurve* c = matching_curve(predicted, s)) {
            const bool creep = s.quantity == Quantity::CreepStrain || s.quantity == Quantity::CreepDeformation;
            const std::vector<double>& xm = creep ? c->time_s : c->axial_strain;
            const std::vector<double>& ym = s.quantity == Quantity::Deviator          ? c->deviator_pa
                                            : s.quantity == Quantity::Volumetric      ? c->volumetric_strain
                                            : s.quantity == Quantity::CreepDeformation ? c->axial_deformation_m
                                                                                      : c->axial_strain;
            if (!xm.empty() && xm.size() == ym.size()) {
                const auto m = compare_curve(xm, ym, s.x, s.lab);
                // compare_curve keeps reading order and drops out-of-range readings; match by abscissa.
                std::size_t j = 0;
                for (std::size_t i = 0; i < s.x.size() && j < m.points.size(); ++i)
                    if (m.points[j].x == s.x[i] && m.points[j].lab == s.lab[i]) model[i] = m.points[j++].model;
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
