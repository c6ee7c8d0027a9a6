#include "server/io/lab_stage_kind.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

// Rules, in the order they are tried (n readings, q in kPa):
//  1. fewer than 3 readings: ambiguous.
//  2. The held part is the longest run of readings at the end of the stage within 5 % of
//     the median of the last fifth (at least 3 readings); an isolated reading outside the
//     band between two inside it is a spike and does not end the run. A hold needs >= 3
//     readings, a median above 1 kPa and at most 10 % spikes.
//  3. The whole stage holds: creep (no ramp).
//  4. A ramp then a hold, the ramp never above the band (a shear's peak is): with a clock
//     and a deformation,
//       - a run of >= 3 ramp readings within 5 % of the run's first (above 1 kPa) lasting
//         over half the ramp's time is an earlier held load step: ambiguous (one stage
//         number per load step);
//     then compare the ramp's mean deformation rate with the hold's:
//       - the deformation must grow during the hold (creep) - else ambiguous;
//       - rate drops >= 3x and the ramp lasts <= 1/4 of the hold: creep, a loading step;
//       - rates within 1.5x of each other: a strain-driven curve, tested as shear below;
//       - anything between: ambiguous.
//     Without a deformation column the two cannot be told apart: ambiguous. Without a
//     clock there is no creep curve: tested as shear.
//  5. Shear: q rises by at least half its peak (and above 1 kPa); before the peak it never
//     falls more than 10 % of the peak below its running maximum, after the peak it never
//     climbs more than 10 % of the peak above its running minimum (softening and plateaus
//     pass, random q does not); the deformation, if measured, grows and never steps back
//     more than 1 % of its range; with a clock and >= 8 readings its rate over each quarter
//     of the stage's duration is within 3x of the others (a shear runs at a set rate; a
//     stage of load steps and holds does not). The rate is checked before the step back,
//     which creep-sized deformations show from reading noise alone.
namespace triax::io {

namespace {

constexpr double kBand = 0.05;           // q held: within 5 % of the held value
constexpr std::size_t kMinHold = 3;      // readings
constexpr double kMinHeldQ = 1.0;        // kPa
constexpr double kSpikeShare = 0.10;     // of the held readings
constexpr double kRateDrop = 3.0;        // loading step vs the creep after it
constexpr double kShortRamp = 0.25;      // ramp duration / hold duration
constexpr double kEarlierHold = 0.5;     // of the ramp's duration, a held level inside it
constexpr double kSameRate = 1.5;        // ramp and plateau of a strain-driven curve
constexpr double kRise = 0.5;            // of the peak
constexpr double kShapeSlack = 0.10;     // of the peak
constexpr double kStrainSlack = 0.01;    // of the deformation range
constexpr double kSteadyRate = 3.0;      // max/min of the quarter rates
constexpr std::size_t kMinForRate = 8;   // readings

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

struct Hold {
    std::size_t begin = 0;  // first held reading; == n when the last reading is outside
    double q = 0.0;         // median of the held readings
    std::size_t spikes = 0;
};

Hold trailing_hold(const std::vector<double>& q) {
    const std::size_t n = q.size();
    const std::size_t tail = std::min(n, std::max(kMinHold, n / 5));
    const double ref = median(std::vector<double>(q.end() - static_cast<std::ptrdiff_t>(tail), q.end()));
    auto inside = [&](std::size_t i) { return std::abs(q[i] - ref) <= kBand * std::abs(ref); };
    Hold h;
    for (std::size_t i = n; i-- > 0;) {
        if (inside(i)) continue;
        const bool spike = i > 0 && i + 1 < n && inside(i - 1) && inside(i + 1);
        if (!spike) {
            h.begin = i + 1;
            break;
        }
    }
    if (h.begin == n) return h;
    h.q = median(std::vector<double>(q.begin() + static_cast<std::ptrdiff_t>(h.begin), q.end()));
    for (std::size_t i = h.begin; i < n; ++i) h.spikes += inside(i) ? 0 : 1;
    return h;
}

StageKind verdict(StageKind::Verdict v, std::string reason, std::size_t hold_begin = 0, double held_q = 0.0) {
    StageKind k;
    k.verdict = v;
    k.reason = std::move(reason);
    k.hold_begin = hold_begin;
    k.held_q = held_q;
    return k;
}

StageKind ambiguous(std::string reason) { return verdict(StageKind::Verdict::Ambiguous, std::move(reason)); }

// Rule 5.
StageKind shear_or_ambiguous(const StageReadings& r, bool timed, bool deformed) {
    const auto& q = r.q;
    const std::size_t n = q.size();
    const auto line = [&](std::size_t i) { return "line " + std::to_string(r.line[i]); };
    const std::size_t p = static_cast<std::size_t>(std::max_element(q.begin(), q.end()) - q.begin());
    const double peak = q[p];
    const double low = *std::min_element(q.begin(), q.begin() + static_cast<std::ptrdiff_t>(p) + 1);
    if (!(peak > kMinHeldQ) || peak - low < kRise * peak)
        return ambiguous("q neither holds within 5 % nor rises to a peak (it rises by " + num(peak - low) +
                         " kPa to its largest value " + num(peak) + " kPa)");
    double top = q[0];
    for (std::size_t i = 1; i <= p; ++i) {
        top = std::max(top, q[i]);
        if (top - q[i] > kShapeSlack * peak)
            return ambiguous("q falls " + num(100.0 * (top - q[i]) / peak) + " % of its peak at " + line(i) +
                             " before reaching the peak at " + line(p) + "; a shear curve rises to its peak");
    }
    double bottom = peak;
    for (std::size_t i = p + 1; i < n; ++i) {
        bottom = std::min(bottom, q[i]);
        if (q[i] - bottom > kShapeSlack * peak)
            return ambiguous("q climbs again by " + num(100.0 * (q[i] - bottom) / peak) + " % of its peak at " + line(i) +
                             " after falling from the peak at " + line(p) + "; a shear curve softens or plateaus");
    }
    if (deformed) {
        const auto& e = r.deformation;
        const auto [lo, hi] = std::minmax_element(e.begin(), e.end());
        if (!(e[n - 1] > e[0])) return ambiguous("q rises but the axial deformation does not grow");
        const auto& t = r.time;
        const bool forward = timed && std::is_sorted(t.begin(), t.end()) && t[n - 1] > t[0];
        if (forward && n >= kMinForRate) {
            // e at the quarters of the stage's duration, linearly interpolated in time.
            auto at = [&](double tq) {
                const auto it = std::lower_bound(t.begin(), t.end(), tq);
                const std::size_t j = static_cast<std::size_t>(it - t.begin());
                if (j == 0) return e[0];
                if (j >= n) return e[n - 1];
                const double w = t[j] > t[j - 1] ? (tq - t[j - 1]) / (t[j] - t[j - 1]) : 1.0;
                return e[j - 1] + w * (e[j] - e[j - 1]);
            };
            double rmin = std::numeric_limits<double>::infinity(), rmax = 0.0;
            for (int k = 0; k < 4; ++k) {
                const double d = at(t[0] + (k + 1) * 0.25 * (t[n - 1] - t[0])) - at(t[0] + k * 0.25 * (t[n - 1] - t[0]));
                rmin = std::min(rmin, d);
                rmax = std::max(rmax, d);
            }
            if (!(rmin > 0.0) || rmax > kSteadyRate * rmin)
                return ambiguous("q rises like a shear curve, but the axial deformation rate is not steady (it varies " +
                                 (rmin > 0.0 ? num(rmax / rmin) + "x" : std::string("down to 0")) +
                                 " between quarters of the stage's time); a shear runs at a set strain rate "
                                 "(several load steps under one stage number? number each)");
        }
        double far = e[0];
        for (std::size_t i = 1; i < n; ++i) {
            far = std::max(far, e[i]);
            if (far - e[i] > kStrainSlack * (*hi - *lo))
                return ambiguous("the axial deformation steps back at " + line(i) +
                                 "; a shear's axial strain grows monotonically");
        }
    }
    return verdict(StageKind::Verdict::Shear, "q rises to a peak of " + num(peak) + " kPa at " + line(p) +
                                                  (p + 1 < n ? ", then softens or plateaus" : ""));
}

}  // namespace

StageKind classify_stage(const StageReadings& r) {
    const auto& q = r.q;
    const std::size_t n = q.size();
    if (n < kMinHold) return ambiguous("fewer than 3 readings");
    const bool timed = r.time.size() == n;
    const bool deformed = r.deformation.size() == n;
    const auto line = [&](std::size_t i) { return "line " + std::to_string(r.line[i]); };

    const Hold hold = trailing_hold(q);
    const std::size_t held_n = n - hold.begin;
    const bool holds = held_n >= kMinHold && hold.q > kMinHeldQ &&
                       static_cast<double>(hold.spikes) <= kSpikeShare * static_cast<double>(held_n);
    if (holds && hold.begin == 0)
        return verdict(StageKind::Verdict::Creep, "q held at " + num(hold.q) + " kPa within 5 %", 0, hold.q);
    if (holds) {
        const std::size_t h = hold.begin;
        const double ramp_top = *std::max_element(q.begin(), q.begin() + static_cast<std::ptrdiff_t>(h));
        const bool overshoot = ramp_top > (1.0 + kBand) * hold.q;
        const std::string ramp_hold = "q ramps to " + num(hold.q) + " kPa by " + line(h) + " and holds within 5 % to " +
                                      line(n - 1);
        if (!overshoot && timed && !deformed)
            return ambiguous(ramp_hold + ", and without an axial strain or deformation column a creep stage's "
                                         "loading ramp and a shear curve's plateau look alike");
        if (!overshoot && timed && deformed) {
            const auto& t = r.time;
            const auto& e = r.deformation;
            const double ramp_t = t[h] - t[0], hold_t = t[n - 1] - t[h];
            const double ramp_e = e[h] - e[0], hold_e = e[n - 1] - e[h];
            if (hold_t > 0.0 && ramp_t > 0.0) {
                // A run of ramp readings within 5 % of its first, over half the ramp's time:
                // an earlier load step held under the same stage number.
                for (std::size_t i = 0, j; i < h; i = j) {
                    for (j = i + 1; j < h && std::abs(q[j] - q[i]) <= kBand * std::abs(q[i]); ++j) {}
                    if (j - i >= kMinHold && std::abs(q[i]) > kMinHeldQ && t[j - 1] - t[i] > kEarlierHold * ramp_t)
                        return ambiguous("q holds at " + num(q[i]) + " kPa from " + line(i) + " to " + line(j - 1) +
                                         " and then at " + num(hold.q) + " kPa from " + line(h) +
                                         ": several load steps under one stage number? number each");
                }
            }
            if (hold_t > 0.0) {
                if (!(hold_e > 0.0))
                    return ambiguous(ramp_hold + ", but the axial deformation does not grow while q is held");
                const double hold_rate = hold_e / hold_t;
                const double ramp_rate = ramp_t > 0.0 ? ramp_e / ramp_t
                                                      : (ramp_e > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
                const double drop = ramp_rate / hold_rate;
                const bool short_ramp = ramp_t <= kShortRamp * hold_t;
                if (drop >= kRateDrop && short_ramp)
                    return verdict(StageKind::Verdict::Creep,
                                   ramp_hold + "; the ramp (from " + line(0) + ") deforms " +
                                       (std::isinf(drop) ? std::string("at once") : num(drop) + "x faster") +
                                       " than the hold: its loading step",
                                   h, hold.q);
                if (drop >= kRateDrop)
                    return ambiguous(ramp_hold + ", but the ramp lasts " + num(100.0 * ramp_t / hold_t) +
                                     " % of the hold's time (a loading step lasts at most 25 % of it; "
                                     "several load steps under one stage number? number each)");
                if (drop > kSameRate || drop < 1.0 / kSameRate)
                    return ambiguous(ramp_hold + ", but the deformation rate changes by a factor of " + num(drop) +
                                     " there (a loading step deforms >= 3x faster than the creep after it, "
                                     "a shear keeps its strain rate)");
            }
        }
    }
    return shear_or_ambiguous(r, timed, deformed);
}

}  // namespace triax::io
