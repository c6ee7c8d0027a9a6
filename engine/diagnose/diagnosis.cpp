// The loop: calibrate the base model, rank the catalog by residual signature, fit the best
// candidates as augmented models, select by BIC, report. Algorithm: docs/diagnosis.md.
#include "engine/diagnose/diagnosis.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <Eigen/Dense>

#include "engine/diagnose/calibration.hpp"
#include "engine/diagnose/model_selection.hpp"
#include "engine/diagnose/residuals.hpp"
#include "engine/diagnose/test_artefacts.hpp"

namespace triax::diagnose {

namespace {

// Below this share of the residual along its signature an effect is not worth fitting.
constexpr double kMinimumScore = 0.05;
// An effect that is off at its lower bound and fitted within this share of its range from
// it is not named: on a DEM model a change of a few % of a range moves q by 10-28 %
// (docs/diagnosis.md section 8.1), so a gain found there is a chance hit on the rough
// objective, not the effect (measured on the CI control with 60 readings: rolling friction
// 0.02 of 0.5 fitted the lab specimen's packing, NRMSE 5.4 % -> 3.7 %, delta BIC -12.9).
constexpr double kMinimumSwitch = 0.1;

// A model variant: the base plus a list of effects; parameters laid out base first.
struct Variant {
    std::vector<Effect> effects;
};

struct Fit {
    Variant variant;
    std::vector<ParameterSpec> specs;
    CalibrationResult cal;
    double bic = 0.0;
};

class Loop {
public:
    Loop(const LabDataset& lab, const ForwardModel& model, const DiagnoseOptions& opt, DiagnoseObserver& obs)
        : model_(model), opt_(opt), obs_(obs), layout_(residual_layout(lab)), ranges_(series_ranges(layout_)),
          base_specs_(model.base_parameters()) {
        if (base_specs_.empty()) throw std::invalid_argument("forward model has no base parameter to calibrate");
        for (Effect e : kAllEffects) {
            if (model.includes(e)) continue;
            auto specs = is_test_artefact(e) ? artefact_parameters(e) : model.effect_parameters(e);
            if (!specs.empty()) effect_specs_[e] = std::move(specs);
            else if (!is_test_artefact(e)) not_offered_.push_back(e);
        }
        int physical = 0;
        for (const auto& [e, s] : effect_specs_) physical += is_test_artefact(e) ? 0 : 1;
        planned_runs_ = opt_.budget_runs + 2 * static_cast<int>(base_specs_.size() + 2) +
                        opt_.max_effects * (physical + (opt_.max_candidates + 1) * std::max(opt_.refine_runs, 1));
    }

    DiagnosisReport run();
    std::vector<CandidateResult> rank_at(const std::vector<double>& base_values);

private:
    std::vector<ParameterSpec> specs_of(const Variant& v) const {
        auto s = base_specs_;
        for (Effect e : v.effects) s.insert(s.end(), effect_specs_.at(e).begin(), effect_specs_.at(e).end());
        return s;
    }

    // Physical prediction at unit-cube point u: one engine run per distinct physical point
    // (cached, so artefact-only changes cost nothing); artefacts are not applied here.
    LabDataset predict_physical(const Variant& v, const UnitPoint& u) {
        const auto specs = specs_of(v);
        std::vector<double> values(specs.size());
        for (std::size_t j = 0; j < specs.size(); ++j) values[j] = to_parameter(specs[j], u[j]);
        ModelPoint point;
        point.base.assign(values.begin(), values.begin() + static_cast<long>(base_specs_.size()));
        std::size_t at = base_specs_.size();
        for (Effect e : v.effects) {
            const std::size_t m = effect_specs_.at(e).size();
            std::vector<double> p(values.begin() + static_cast<long>(at), values.begin() + static_cast<long>(at + m));
            at += m;
            if (is_test_artefact(e)) continue;
            // An effect at its "off" bound is the model without it (same run, same cache entry).
            const auto& sp = effect_specs_.at(e);
            bool off = true;
            for (std::size_t q = 0; q < m; ++q) off = off && sp[q].lower_is_off && p[q] <= sp[q].lower;
            if (!off) point.effects.emplace_back(e, std::move(p));
        }
        std::sort(point.effects.begin(), point.effects.end());
        std::vector<double> key = point.base;
        for (const auto& [e, p] : point.effects) {
            key.push_back(1000.0 + static_cast<double>(e));
            key.insert(key.end(), p.begin(), p.end());
        }
        {
            std::lock_guard<std::mutex> lock(cache_mutex_);
            auto it = cache_.find(key);
            if (it != cache_.end()) return it->second;
        }
        LabDataset predicted = model_.simulate(point, opt_.seed);
        std::lock_guard<std::mutex> lock(cache_mutex_);
        if (cache_.emplace(key, predicted).second) ++runs_;
        return predicted;
    }

    // Unit-cube coordinates of the variant's test artefacts (one parameter each).
    std::vector<std::pair<std::size_t, Effect>> artefact_coordinates(const Variant& v) const {
        std::vector<std::pair<std::size_t, Effect>> out;
        std::size_t at = base_specs_.size();
        for (Effect e : v.effects) {
            if (is_test_artefact(e)) out.emplace_back(at, e);
            at += effect_specs_.at(e).size();
        }
        return out;
    }

    std::vector<double> with_artefacts(const Variant& v, const LabDataset& physical, const UnitPoint& u) const {
        LabDataset d = physical;
        for (const auto& [j, e] : artefact_coordinates(v))
            apply_test_artefact(d, e, {to_parameter(effect_specs_.at(e)[0], u[j])});
        return normalised_residual(layout_, d);
    }

    // Residual at u. With `polish`, the artefact coordinates of u are first set to their
    // optimum for this engine run (coarse grid, then golden section; two sweeps when there
    // are two artefacts): they cost no run, so the calibration treats them as profiled.
    std::vector<double> residual_at(const Variant& v, UnitPoint& u, bool polish) {
        const LabDataset physical = predict_physical(v, u);
        const auto coords = artefact_coordinates(v);
        if (!polish || coords.empty()) return with_artefacts(v, physical, u);
        auto rss_at = [&](const UnitPoint& x) { return residual_sum_of_squares(with_artefacts(v, physical, x)); };
        double best = rss_at(u);
        for (int sweep = 0; sweep < (coords.size() > 1 ? 2 : 1); ++sweep)
            for (const auto& [j, e] : coords) {
                UnitPoint x = u;
                for (int g = 0; g <= 20; ++g) {
                    x[j] = g / 20.0;
                    const double r = rss_at(x);
                    if (r < best) best = r, u[j] = x[j];
                }
                double lo = std::max(0.0, u[j] - 0.05), hi = std::min(1.0, u[j] + 0.05);
                const double phi = 0.5 * (std::sqrt(5.0) - 1.0);
                double x1 = hi - phi * (hi - lo), x2 = lo + phi * (hi - lo);
                x[j] = x1;
                double f1 = rss_at(x);
                x[j] = x2;
                double f2 = rss_at(x);
                for (int it = 0; it < 14; ++it) {
                    if (f1 < f2) {
                        hi = x2, x2 = x1, f2 = f1, x1 = hi - phi * (hi - lo), x[j] = x1, f1 = rss_at(x);
                    } else {
                        lo = x1, x1 = x2, f1 = f2, x2 = lo + phi * (hi - lo), x[j] = x2, f2 = rss_at(x);
                    }
                }
                if (std::min(f1, f2) < best) best = std::min(f1, f2), u[j] = f1 < f2 ? x1 : x2;
            }
        return with_artefacts(v, physical, u);
    }

    // Independent evaluations spread over opt.concurrency threads; a failed run gives an
    // empty residual (the calibration treats it as infinitely bad). With `polish` the
    // artefact coordinates of the points are replaced by their optimum.
    std::vector<std::vector<double>> evaluate(const Variant& v, std::vector<UnitPoint>& batch, bool polish = true) {
        if (obs_.cancelled()) throw DiagnosisCancelled{};
        std::vector<std::vector<double>> out(batch.size());
        std::atomic<std::size_t> next{0};
        auto worker = [&] {
            for (std::size_t i; (i = next.fetch_add(1)) < batch.size();) {
                try {
                    out[i] = residual_at(v, batch[i], polish);
                } catch (const DiagnosisCancelled&) {
                    out[i].clear();
                } catch (const std::exception&) {
                    out[i].clear();
                    failures_.fetch_add(1);
                }
            }
        };
        const std::size_t threads = std::min<std::size_t>(static_cast<std::size_t>(std::max(opt_.concurrency, 1)), batch.size());
        std::vector<std::thread> pool;
        for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(worker);
        worker();
        for (auto& t : pool) t.join();
        report_progress();
        return out;
    }

    void report_progress() {
        const double pct = std::min(99.0, 100.0 * static_cast<double>(runs_.load()) / std::max(planned_runs_, 1));
        obs_.on_progress(pct, stage_);
        if (obs_.cancelled()) throw DiagnosisCancelled{};
    }

    Fit fit(const Variant& v, const UnitPoint& start, int design_runs, int refine_runs, bool axial,
            const CalibrationResult* history = nullptr, std::vector<UnitPoint> extra_design = {}, int local_starts = 1) {
        Fit f{v, specs_of(v), {}, 0.0};
        CalibrationSettings st;
        st.start = start;
        st.design_runs = design_runs;
        st.refine_runs = refine_runs;
        st.batch = std::max(1, opt_.concurrency);
        st.seed = opt_.seed;
        st.axial_design = axial;
        st.history = history;
        st.extra_design = std::move(extra_design);
        st.local_starts = local_starts;
        st.initial_radius = axial ? 0.15 : 0.25;
        st.profiled.assign(f.specs.size(), false);
        for (const auto& [j, e] : artefact_coordinates(v)) st.profiled[j] = true;
        f.cal = calibrate([&](std::vector<UnitPoint>& b) { return evaluate(v, b); }, st);
        return f;
    }

    // The variant v fitted from runs already made (no new engine run): every point of
    // `source` mapped onto v's coordinates (shared parameters kept, the others nominal),
    // artefacts polished, the best kept. Valid when v's physical part is source's.
    Fit refit_free(const Variant& v, const Fit& source) {
        Fit f{v, specs_of(v), {}, 0.0};
        std::vector<UnitPoint> points;
        for (const auto& u : source.cal.points) points.push_back(project(source.variant, u, v));
        CalibrationResult h;
        if (!points.empty()) {
            auto r = evaluate(v, points);
            for (std::size_t i = 0; i < points.size(); ++i) {
                h.points.push_back(points[i]);
                h.point_rss.push_back(r[i].empty() ? std::numeric_limits<double>::infinity() : residual_sum_of_squares(r[i]));
                h.point_residuals.push_back(std::move(r[i]));
            }
        }
        const auto best = std::min_element(h.point_rss.begin(), h.point_rss.end()) - h.point_rss.begin();
        // A calibration with no new point: collects the history and fits the surrogate.
        f.cal = fit(v, h.points.empty() ? project(source.variant, source.cal.best, v) : h.points[static_cast<std::size_t>(best)],
                    0, 0, false, &h).cal;
        return f;
    }

    // Coordinates of `u` (a point of variant `from`) in variant `to`.
    UnitPoint project(const Variant& from, const UnitPoint& u, const Variant& to) const {
        UnitPoint out(u.begin(), u.begin() + static_cast<long>(base_specs_.size()));
        for (Effect e : to.effects) {
            std::size_t at = base_specs_.size();
            bool found = false;
            for (Effect g : from.effects) {
                const std::size_t m = effect_specs_.at(g).size();
                if (g == e) {
                    out.insert(out.end(), u.begin() + static_cast<long>(at), u.begin() + static_cast<long>(at + m));
                    found = true;
                    break;
                }
                at += m;
            }
            if (!found) {
                const UnitPoint extra = nominal_unit(effect_specs_.at(e));
                out.insert(out.end(), extra.begin(), extra.end());
            }
        }
        return out;
    }

    UnitPoint nominal_unit(const std::vector<ParameterSpec>& specs) const {
        UnitPoint u(specs.size());
        for (std::size_t j = 0; j < specs.size(); ++j) u[j] = to_unit(specs[j], specs[j].nominal);
        return u;
    }

    UnitPoint extended(UnitPoint u, Effect e) const {
        const UnitPoint extra = nominal_unit(effect_specs_.at(e));
        u.insert(u.end(), extra.begin(), extra.end());
        return u;
    }

    // Replaces the surrogate Jacobian of a fit by forward differences at its optimum (k runs,
    // step 0.03 of each parameter's range, taken inward from the bounds): the reported
    // uncertainties must not depend on how the refinement happened to scatter its runs.
    // With `artefacts_only` just the artefact columns are replaced (they cost no run).
    void finite_difference_jacobian(Fit& f, bool artefacts_only = false) {
        const std::size_t k = f.cal.best.size(), n = f.cal.residual.size();
        if (f.cal.jacobian.size() != n * k) f.cal.jacobian.assign(n * k, 0.0);
        std::vector<std::size_t> cols;
        if (artefacts_only)
            for (const auto& [j, e] : artefact_coordinates(f.variant)) cols.push_back(j);
        else
            for (std::size_t j = 0; j < k; ++j) cols.push_back(j);
        if (cols.empty()) return;
        std::vector<UnitPoint> probes;
        std::vector<double> steps;
        for (std::size_t j : cols) {
            UnitPoint u = f.cal.best;
            const double h = u[j] + 0.03 <= 1.0 ? 0.03 : -0.03;
            u[j] += h;
            probes.push_back(u);
            steps.push_back(h);
        }
        const auto r = evaluate(f.variant, probes, false);
        std::vector<double> J = f.cal.jacobian;
        for (std::size_t c = 0; c < cols.size(); ++c) {
            if (r[c].size() != n) return;  // a failed probe: keep the surrogate Jacobian
            for (std::size_t i = 0; i < n; ++i) J[cols[c] * n + i] = (r[c][i] - f.cal.residual[i]) / steps[c];
        }
        f.cal.jacobian = std::move(J);
    }

    std::vector<FittedParameter> parameters_of(const Fit& f, double n_eff) const {
        const auto stds = parameter_std(f.specs, f.cal, n_eff);
        std::vector<FittedParameter> out;
        for (std::size_t j = 0; j < f.specs.size(); ++j)
            out.push_back({f.specs[j].name, f.specs[j].unit, to_parameter(f.specs[j], f.cal.best[j]),
                           stds[j]});
        return out;
    }

    double score_signature(const Fit& current, const std::vector<double>& with_effect) const;

    // Line search along a one-parameter effect: the candidate fit then has the effect at
    // off, nominal and further on two lines (the current base, and the prior when
    // `with_prior_line`); the minimum of a parabola of the RSS through each line's three runs
    // is returned as a further probe. The response can be steep between them: on the DEM
    // crushing case (pair 7/11) the prior with crushability 1 fitted at 29.0 %, the truth
    // 0.75 at 14.2 %, and the parabola through 0 / 1 / 1.8 pointed at 0.71
    // (docs/diagnosis.md 8.9). `probes` is {further, restart, [at_prior]} as the caller
    // builds them; every run here is cached for the fit that follows.
    std::vector<UnitPoint> line_search_probes(const Variant& v, const UnitPoint& start,
                                              const std::vector<UnitPoint>& probes, bool with_prior_line) {
        std::vector<UnitPoint> line = probes;
        line.push_back(start);
        const auto r = evaluate(v, line);
        const std::size_t q = start.size() - 1;
        auto rss_off = [&](const UnitPoint& u) {
            UnitPoint o = u;
            o[q] = 0.0;
            std::vector<UnitPoint> b{o};
            const auto ro = evaluate(v, b);  // the model without the effect: cached
            return ro[0].empty() ? std::numeric_limits<double>::infinity() : residual_sum_of_squares(ro[0]);
        };
        auto rss_of = [&](std::size_t i) {
            return r[i].empty() ? std::numeric_limits<double>::infinity() : residual_sum_of_squares(r[i]);
        };
        // (index of nominal, index of further) on each line: current base, prior.
        std::vector<std::pair<std::size_t, std::size_t>> lines{{line.size() - 1, 0}};
        if (with_prior_line) lines.emplace_back(2, 1);
        std::vector<UnitPoint> out;
        for (const auto& [i_nom, i_far] : lines) {
            const double x0 = 0.0, x1 = line[i_nom][q], x2 = line[i_far][q];
            const double f0 = rss_off(line[i_nom]), f1 = rss_of(i_nom), f2 = rss_of(i_far);
            if (!std::isfinite(f0 + f1 + f2) || x1 <= x0 || x2 <= x1) continue;
            // Divided differences: f = f0 + d1 x + a x (x - x1).
            const double d1 = (f1 - f0) / (x1 - x0), d2 = (f2 - f1) / (x2 - x1);
            const double a = (d2 - d1) / (x2 - x0);
            if (a <= 0.0) continue;
            const double xm = std::clamp(0.5 * (x1 - d1 / a), 0.5 * kMinimumSwitch, 1.0);
            if (std::abs(xm - x1) < 0.03 || std::abs(xm - x2) < 0.03) continue;
            UnitPoint p = line[i_nom];
            p[q] = xm;
            out.push_back(std::move(p));
        }
        return out;
    }


    // Points at which effect e's signature is taken at `current`: its parameters at their
    // nominal; for an effect with several parameters each off at its lower bound (grain
    // breakage with creep curves of a bonded specimen: crushability and extra bond damage),
    // one point per parameter with the others off, because data may carry one mechanism
    // without the other. Measured on the analytic creep case with only the bond damage:
    // with both parameters on, crushing's shear change hid the creep match (score 0.09
    // against contact viscosity's 0.18); alone, the damage scores highest.
    std::vector<UnitPoint> signature_points(const UnitPoint& current, Effect e) const {
        const auto& sp = effect_specs_.at(e);
        const bool separable = sp.size() > 1 && std::all_of(sp.begin(), sp.end(), [](auto& p) { return p.lower_is_off; });
        if (!separable) return {extended(current, e)};
        std::vector<UnitPoint> out;
        for (std::size_t j = 0; j < sp.size(); ++j) {
            UnitPoint u = current;
            for (std::size_t q = 0; q < sp.size(); ++q) u.push_back(q == j ? to_unit(sp[q], sp[q].nominal) : 0.0);
            out.push_back(std::move(u));
        }
        return out;
    }

    // The effect's signature score at `current` (the best over its signature points) and
    // the point that gave it, where a fit of the effect starts.
    CandidateResult signature_of(const Fit& current, Effect e, UnitPoint& best_point) {
        Variant v = current.variant;
        v.effects.push_back(e);
        std::vector<UnitPoint> at = signature_points(current.cal.best, e);
        const auto r = evaluate(v, at, false);
        CandidateResult c;
        c.effect = std::string(effect_name(e));
        best_point = at.front();
        bool failed = false;
        for (std::size_t i = 0; i < at.size(); ++i) {
            if (r[i].empty()) {
                failed = true;
                continue;
            }
            const double score = score_signature(current, r[i]);
            if (score > c.signature_score || i == 0) c.signature_score = std::max(score, c.signature_score), best_point = at[i];
        }
        if (failed) c.note = "signature run failed";
        return c;
    }

    // Every "off at the lower bound" parameter of the fit's last effect is within
    // kMinimumSwitch of its range from off (false for effects without an off value).
    bool barely_on(const Fit& f) const {
        if (f.variant.effects.empty()) return false;
        const auto& sp = effect_specs_.at(f.variant.effects.back());
        const std::size_t at = f.cal.best.size() - sp.size();
        for (std::size_t q = 0; q < sp.size(); ++q)
            if (!sp[q].lower_is_off || f.cal.best[at + q] >= kMinimumSwitch) return false;
        return true;
    }

    const ForwardModel& model_;
    const DiagnoseOptions& opt_;
    DiagnoseObserver& obs_;
    std::vector<ResidualSeries> layout_;
    std::vector<std::pair<std::size_t, std::size_t>> ranges_;
    std::vector<ParameterSpec> base_specs_;
    std::map<Effect, std::vector<ParameterSpec>> effect_specs_;
    // Catalog effects the model cannot show on these data (e.g. the DEM's grain breakage
    // acts in creep stages only): never candidates, and the verdict says so.
    std::vector<Effect> not_offered_;
    std::map<std::vector<double>, LabDataset> cache_;
    std::mutex cache_mutex_;
    std::atomic<int> failures_{0};
    std::atomic<int> runs_{0};
    int planned_runs_ = 1;
    std::string stage_ = "calibration";
};

// Score test: how much of the current residual lies along the effect's signature once the
// directions the current parameters can already produce (columns of J) are projected out.
// Only the direction that reduces the residual counts (effects are switched on from zero).
double Loop::score_signature(const Fit& current, const std::vector<double>& with_effect) const {
    const auto& r0 = current.cal.residual;
    if (with_effect.size() != r0.size()) return 0.0;
    const Eigen::Index n = static_cast<Eigen::Index>(r0.size());
    Eigen::VectorXd s(n), r(n);
    for (Eigen::Index i = 0; i < n; ++i) s[i] = with_effect[static_cast<std::size_t>(i)] - r0[static_cast<std::size_t>(i)], r[i] = r0[static_cast<std::size_t>(i)];
    const Eigen::Index k = static_cast<Eigen::Index>(current.cal.best.size());
    if (k > 0 && static_cast<Eigen::Index>(current.cal.jacobian.size()) == n * k) {
        const Eigen::Map<const Eigen::MatrixXd> J(current.cal.jacobian.data(), n, k);
        Eigen::MatrixXd jtj = J.transpose() * J;
        jtj.diagonal().array() += 1e-9 * std::max(jtj.trace(), 1e-12);
        s -= J * jtj.ldlt().solve(J.transpose() * s);
    }
    const double denom = s.norm() * r.norm();
    if (denom <= 0.0) return 0.0;
    return std::max(0.0, -r.dot(s) / denom);
}

DiagnosisReport Loop::run() {
    DiagnosisReport rep;
    const std::size_t n = layout_.empty() ? 0 : ranges_.back().second;

    // 1. Base calibration with every test artefact profiled: they cost no run, so each
    //    engine run is scored with the artefacts at their best, and an artefact cannot pull
    //    the physical parameters away while the calibration tries to mimic it.
    stage_ = "calibration";
    Variant artefacts;
    for (const auto& [e, specs] : effect_specs_)
        if (is_test_artefact(e)) artefacts.effects.push_back(e);
    UnitPoint start = nominal_unit(base_specs_);
    for (Effect e : artefacts.effects) start = extended(start, e);
    const int design = std::max(2, opt_.budget_runs / 2);
    const Fit calib = fit(artefacts, start, design - 1, std::max(0, opt_.budget_runs - design), false);
    if (!std::isfinite(calib.cal.rss))
        throw std::runtime_error("every base-model run failed (" + std::to_string(failures_.load()) +
                                 " failures); check the scheme");

    // Per step: BIC of each fitted candidate, and of the step's winner, for runners-up.
    std::vector<std::vector<std::pair<std::string, double>>> step_bics;
    std::vector<double> step_winner_bic;
    int step = 0;

    // Records a step's candidates and picks the winner by BIC (one n_eff for all, from the
    // best-fitting model's residual); returns the index of the winner in `fits` or -1.
    auto select = [&](Fit& same, std::vector<Fit>& fits, std::vector<CandidateResult>& cands) -> int {
        const Fit* best_fit = &same;
        for (const auto& f : fits)
            if (f.cal.rss < best_fit->cal.rss) best_fit = &f;
        const double n_eff = effective_readings(best_fit->cal.residual, ranges_);
        same.bic = bic(same.cal.rss, n, n_eff, same.specs.size());
        int winner = -1;
        std::vector<std::pair<std::string, double>> bics;
        for (std::size_t i = 0; i < fits.size(); ++i) {
            auto& f = fits[i];
            f.bic = std::isfinite(f.cal.rss) ? bic(f.cal.rss, n, n_eff, f.specs.size()) : std::numeric_limits<double>::infinity();
            auto& c = *std::find_if(cands.begin(), cands.end(), [&](auto& x) { return x.effect == effect_name(f.variant.effects.back()); });
            c.fitted = true;
            c.rss = f.cal.rss;
            c.nrmse = std::sqrt(f.cal.rss / static_cast<double>(n));
            c.bic = f.bic;
            c.delta_bic_vs_base = f.bic - same.bic;
            auto all = parameters_of(f, n_eff);
            c.parameters.assign(all.end() - static_cast<long>(effect_specs_.at(f.variant.effects.back()).size()), all.end());
            bics.emplace_back(c.effect, f.bic);
            if (f.bic < same.bic - opt_.bic_threshold && barely_on(f)) {
                std::ostringstream why;
                why << "not named: fitted within " << 100.0 * kMinimumSwitch
                    << " % of its range from off, the scale at which a DEM response is rough (a chance gain)";
                c.note = why.str();
                continue;
            }
            if (f.bic < same.bic - opt_.bic_threshold && (winner < 0 || f.bic < fits[static_cast<std::size_t>(winner)].bic))
                winner = static_cast<int>(i);
        }
        std::stable_sort(cands.begin(), cands.end(), [](auto& a, auto& b) {
            if (a.fitted != b.fitted) return a.fitted;
            return a.fitted ? a.bic < b.bic : a.signature_score > b.signature_score;
        });
        for (const auto& c : cands) obs_.on_candidate(c);
        rep.candidates.insert(rep.candidates.end(), cands.begin(), cands.end());
        SelectionStep st;
        st.step = step;
        st.nrmse_before = std::sqrt(same.cal.rss / static_cast<double>(n));
        st.nrmse_after = st.nrmse_before;
        st.n_effective = n_eff;
        step_bics.push_back(bics);
        step_winner_bic.push_back(winner >= 0 ? fits[static_cast<std::size_t>(winner)].bic : same.bic);
        if (winner >= 0) {
            const auto& w = fits[static_cast<std::size_t>(winner)];
            st.added = std::string(effect_name(w.variant.effects.back()));
            st.nrmse_after = std::sqrt(w.cal.rss / static_cast<double>(n));
            st.delta_bic = w.bic - same.bic;
        }
        rep.steps.push_back(st);
        return winner;
    };

    // Where each candidate's fit starts: the signature point that scored best.
    std::map<Effect, UnitPoint> signature_start;
    auto signature_candidate = [&](const Fit& current, Effect e) {
        CandidateResult c = signature_of(current, e, signature_start[e]);
        c.step = step;
        return c;
    };

    // 2. The artefacts stay in every model as nuisance parameters (profiled, free) while
    //    physical effects are tried, so no physical candidate is charged for, or credited
    //    with, a seating offset or a membrane; which artefacts the data really show is
    //    decided at the end (backward pass). Selecting them up front by BIC failed on DEM
    //    data: with few effective readings a 0.3 % seating offset did not earn its
    //    parameter against a base model that mimicked it, and every later fit carried it.
    Fit current = calib;

    // 3. Physical effects, stepwise.
    Fit base_source = current;  // runs of the model without physical effects
    bool first_physical = true;
    for (int physical_step = 1; physical_step <= opt_.max_effects; ++physical_step) {
        stage_ = "signatures";
        std::vector<Effect> pool;
        for (const auto& [e, specs] : effect_specs_)
            if (std::find(current.variant.effects.begin(), current.variant.effects.end(), e) == current.variant.effects.end())
                pool.push_back(e);
        if (std::none_of(pool.begin(), pool.end(), [](Effect e) { return !is_test_artefact(e); })) break;
        ++step;
        // The current model refined with the same run budget a candidate gets, so no
        // candidate wins merely by being calibrated longer. Done before the ranking, so the
        // signatures are taken at the point the candidates start from (one run per
        // candidate serves as both; measured: a run saved per step on the CI DEM case).
        Fit same = fit(current.variant, current.cal.best, 0, opt_.refine_runs, false, &current.cal);
        if (same.cal.rss > current.cal.rss) same = current;
        if (first_physical) base_source = same;
        first_physical = false;

        finite_difference_jacobian(same, true);
        std::vector<CandidateResult> cands;
        std::vector<std::pair<double, Effect>> ranked;
        for (Effect e : pool) {
            cands.push_back(signature_candidate(same, e));
            if (!is_test_artefact(e)) ranked.emplace_back(cands.back().signature_score, e);
        }
        std::stable_sort(ranked.begin(), ranked.end(), [](auto& a, auto& b) { return a.first > b.first; });
        stage_ = "candidates";

        std::vector<Fit> fits;
        for (std::size_t i = 0; i < ranked.size() && static_cast<int>(i) < opt_.max_candidates; ++i) {
            const Effect e = ranked[i].second;
            auto& c = *std::find_if(cands.begin(), cands.end(), [&](auto& x) { return x.effect == effect_name(e); });
            if (ranked[i].first < kMinimumScore) {
                c.note = "signature does not match the residual (score < 0.05)";
                continue;
            }
            Variant v = current.variant;
            v.effects.push_back(e);
            const auto& especs = effect_specs_.at(e);
            const bool seeded = std::all_of(especs.begin(), especs.end(), [](auto& p) { return p.lower_is_off; });
            if (seeded) {
                // The runs of the current model are this model with the effect off: they seed
                // the surrogate, so only the effect's own direction needs new runs.
                CalibrationResult h;
                for (std::size_t q = 0; q < same.cal.points.size(); ++q) {
                    UnitPoint u = same.cal.points[q];
                    u.insert(u.end(), especs.size(), 0.0);
                    h.points.push_back(u);
                    h.point_rss.push_back(same.cal.point_rss[q]);
                    h.point_residuals.push_back(same.cal.point_residuals[q]);
                }
                // Plus one probe further along the effect (a large lever against DEM noise),
                // and two from the scheme's nominal base (the prior), with the effect there
                // and at its nominal: the base optimum may have drifted to mimic the effect
                // with other parameters (friction, bonds), and the way back is a valley that
                // local steps rarely find in a few runs. The prior with the effect's nominal
                // is the model's own first guess; without it a strong effect (grain
                // crushing) was probed only from the drifted base or far beyond its nominal
                // (measured on the DEM crushing case: step cut 49.6 %, friction 0.17 for 0.4).
                UnitPoint start = signature_start.count(e) ? signature_start[e] : extended(same.cal.best, e), further = start;
                for (std::size_t q = start.size() - especs.size(); q < start.size(); ++q)
                    if (start[q] > 0.0) further[q] = std::min(1.0, start[q] + 0.4);  // an "off" parameter stays off
                const UnitPoint prior = nominal_unit(base_specs_);
                UnitPoint restart = further, at_prior = start;
                std::copy(prior.begin(), prior.end(), restart.begin());
                std::copy(prior.begin(), prior.end(), at_prior.begin());
                std::vector<UnitPoint> probes{further, restart};
                if (at_prior != start) probes.push_back(at_prior);
                // Line search along a one-parameter effect (line_search_probes).
                if (especs.size() == 1) {
                    const auto more = line_search_probes(v, start, probes, at_prior != start);
                    probes.insert(probes.end(), more.begin(), more.end());
                }
                fits.push_back(fit(v, start, 0, opt_.refine_runs, false, &h, std::move(probes), 1));
            } else {
                // Refinement from the current optimum: axial probes then local steps.
                fits.push_back(fit(v, extended(same.cal.best, e), 0, opt_.refine_runs, true));
            }
        }
        for (auto& c : cands)
            if (c.note.empty() && std::none_of(fits.begin(), fits.end(), [&](auto& f) { return effect_name(f.variant.effects.back()) == c.effect; }))
                c.note = "ranked below the top " + std::to_string(opt_.max_candidates);
        const int w = select(same, fits, cands);
        if (w < 0) {
            current = same;
            break;
        }
        current = fits[static_cast<std::size_t>(w)];
    }
    // 4. Backward pass over the artefacts (free): an artefact stays in the final model if
    //    it pays for its parameter at all (BIC lower with it); it is *named* (effects,
    //    chosen_effect) only if it lowers BIC by more than the threshold, like a physical
    //    effect. Dropping a real 0.3 % seating offset because a short DEM curve has few
    //    effective readings would spoil the fitted physics and the error after (measured:
    //    NRMSE 11 % -> 19 % on the CI DEM case), so nuisance and evidence are kept apart.
    std::vector<std::string> dropped;
    for (bool again = true; again;) {
        again = false;
        for (Effect e : current.variant.effects) {
            if (!is_test_artefact(e)) continue;
            Variant v;
            for (Effect g : current.variant.effects)
                if (g != e) v.effects.push_back(g);
            Fit without = refit_free(v, current);
            const double ne = effective_readings(current.cal.residual, ranges_);
            if (bic(without.cal.rss, n, ne, without.specs.size()) <= bic(current.cal.rss, n, ne, current.specs.size())) {
                dropped.emplace_back(effect_name(e));
                current = without;
                again = true;
                break;
            }
        }
    }

    // Each artefact kept is reported as a step of its own: the final model against the
    // final model without it (free), on the final model's n_eff.
    std::vector<Effect> named;  // artefacts with evidence above the threshold
    {
        const double ne = effective_readings(current.cal.residual, ranges_);
        for (Effect e : current.variant.effects) {
            if (!is_test_artefact(e)) continue;
            Variant v;
            for (Effect g : current.variant.effects)
                if (g != e) v.effects.push_back(g);
            const Fit without = refit_free(v, current);
            SelectionStep st;
            st.step = ++step;
            st.added = std::string(effect_name(e));
            st.nrmse_before = std::sqrt(without.cal.rss / static_cast<double>(n));
            st.nrmse_after = std::sqrt(current.cal.rss / static_cast<double>(n));
            st.delta_bic = bic(current.cal.rss, n, ne, current.specs.size()) - bic(without.cal.rss, n, ne, without.specs.size());
            st.n_effective = ne;
            if (st.delta_bic < -opt_.bic_threshold) named.push_back(e);
            rep.steps.push_back(st);
        }
    }

    // The calibrated base model (no effect, no artefact) on every run made without a
    // physical effect: the "before" of the report.
    Fit base_final = refit_free(Variant{}, base_source);

    // 5. Report on one footing: n_eff from the final model's residual.
    const double n_eff = effective_readings(current.cal.residual, ranges_);
    const double bic_base = bic(base_final.cal.rss, n, n_eff, base_final.specs.size());
    const double bic_final = bic(current.cal.rss, n, n_eff, current.specs.size());
    rep.n_readings = static_cast<double>(n);
    rep.n_effective = n_eff;
    stage_ = "uncertainty";
    finite_difference_jacobian(base_final, !opt_.finite_difference_uncertainty);
    if (!current.variant.effects.empty()) finite_difference_jacobian(current, !opt_.finite_difference_uncertainty);
    else current.cal.jacobian = base_final.cal.jacobian;
    rep.base_parameters = parameters_of(base_final, n_eff);
    rep.parameters = parameters_of(current, n_eff);
    rep.error_before = phase_errors(layout_, base_final.cal.residual);
    rep.error_after = phase_errors(layout_, current.cal.residual);
    rep.nrmse_before = std::sqrt(base_final.cal.rss / static_cast<double>(n));
    rep.nrmse_after = std::sqrt(current.cal.rss / static_cast<double>(n));
    rep.delta_bic_vs_base = bic_final - bic_base;
    for (Effect e : current.variant.effects)
        if (!is_test_artefact(e) || std::find(named.begin(), named.end(), e) != named.end())
            rep.effects.emplace_back(effect_name(e));
    // The missing physics is the headline; artefacts found alongside stay in `effects`.
    for (Effect e : current.variant.effects)
        if (!is_test_artefact(e)) {
            rep.chosen_effect = std::string(effect_name(e));
            break;
        }
    if (rep.chosen_effect == "unexplained" && !rep.effects.empty()) rep.chosen_effect = rep.effects.front();
    // Runners-up: the other candidates of the step that selected the chosen effect.
    for (std::size_t k = 0; k < rep.steps.size() && k < step_bics.size(); ++k)
        if (rep.steps[k].added == rep.chosen_effect)
            for (const auto& [name, b] : step_bics[k])
                if (name != rep.chosen_effect) rep.runners_up.push_back({name, b - step_winner_bic[k]});
    rep.runs_used = runs_.load();

    std::ostringstream v;
    v.setf(std::ios::fixed);
    v.precision(1);
    if (rep.effects.empty()) {
        const PhaseError* worst = nullptr;
        for (const auto& e : rep.error_after)
            if (e.phase != "all" && e.n >= 3 && (!worst || e.nrmse > worst->nrmse)) worst = &e;
        v << "unexplained: no effect in the catalog lowers BIC by more than " << opt_.bic_threshold
          << " (n_eff = " << n_eff << " of " << n << " readings); remaining NRMSE " << 100.0 * rep.nrmse_after << " %";
        if (worst) v << ", largest in " << worst->curve << " " << worst->phase << " (" << 100.0 * worst->nrmse << " %)";
    } else {
        v << rep.chosen_effect << " explains the residual";
        for (const auto& e : rep.effects)
            if (e != rep.chosen_effect) v << " (with " << e << ")";
        v << ": delta BIC " << rep.delta_bic_vs_base << " vs the calibrated base model, NRMSE " << 100.0 * rep.nrmse_before
          << " % -> " << 100.0 * rep.nrmse_after << " %";
        if (!rep.runners_up.empty()) {
            auto next = std::min_element(rep.runners_up.begin(), rep.runners_up.end(),
                                         [](auto& a, auto& b) { return a.delta_bic < b.delta_bic; });
            v << "; next best " << next->effect << " is worse by " << next->delta_bic;
        }
    }
    for (Effect e : current.variant.effects)
        if (is_test_artefact(e) && std::find(named.begin(), named.end(), e) == named.end())
            v << "; " << effect_name(e) << " kept as a correction below the evidence threshold";
    for (const auto& d : dropped) v << "; " << d << " dropped (does not lower BIC)";
    // A base parameter at the edge of its prior: the base model is straining, and what it
    // cannot give may be missing physics (or the prior is too narrow for this material).
    for (std::size_t j = 0; j < base_specs_.size() && j < current.cal.best.size(); ++j) {
        const double u = current.cal.best[j];
        if (u > 0.005 && u < 0.995) continue;
        v << "; " << base_specs_[j].name << " at the " << (u <= 0.005 ? "lower" : "upper") << " bound of its prior ("
          << std::defaultfloat << std::setprecision(3) << to_parameter(base_specs_[j], u) << std::fixed
          << std::setprecision(1) << ")";
    }
    if (!not_offered_.empty()) {
        v << "; not testable on these data with this model:";
        for (std::size_t i = 0; i < not_offered_.size(); ++i) v << (i ? ", " : " ") << effect_name(not_offered_[i]);
    }
    v << "; " << runs_.load() << " model runs";
    if (failures_ > 0) v << " (" << failures_.load() << " failed)";
    rep.verdict = v.str();
    obs_.on_progress(100.0, "done");
    return rep;
}

// Signature ranking at a given base point (no calibration): residual there, a forward-
// difference Jacobian (k runs), one run per physical effect.
std::vector<CandidateResult> Loop::rank_at(const std::vector<double>& base_values) {
    if (base_values.size() != base_specs_.size())
        throw std::invalid_argument("rank_effects: expected " + std::to_string(base_specs_.size()) + " base values, got " +
                                    std::to_string(base_values.size()));
    Fit at{Variant{}, base_specs_, {}, 0.0};
    for (std::size_t j = 0; j < base_specs_.size(); ++j) at.cal.best.push_back(to_unit(base_specs_[j], base_values[j]));
    stage_ = "signatures";
    std::vector<UnitPoint> p0{at.cal.best};
    auto r0 = evaluate(at.variant, p0, false);
    if (r0[0].empty()) throw std::runtime_error("rank_effects: the model run at the given point failed");
    at.cal.residual = r0[0];
    at.cal.rss = residual_sum_of_squares(at.cal.residual);
    finite_difference_jacobian(at);
    std::vector<CandidateResult> out;
    for (const auto& [e, specs] : effect_specs_) {
        UnitPoint where;
        out.push_back(signature_of(at, e, where));
    }
    std::stable_sort(out.begin(), out.end(), [](auto& a, auto& b) { return a.signature_score > b.signature_score; });
    return out;
}

}  // namespace

std::vector<CandidateResult> rank_effects(const LabDataset& lab, const ForwardModel& model,
                                          const std::vector<double>& base_values, const DiagnoseOptions& options,
                                          DiagnoseObserver& observer) {
    Loop loop(lab, model, options, observer);
    return loop.rank_at(base_values);
}

DiagnosisReport run_diagnosis(const LabDataset& lab, const ForwardModel& model, const DiagnoseOptions& options,
                              DiagnoseObserver& observer) {
    if (options.budget_runs < 4) throw std::invalid_argument("budget_runs must be at least 4, got " + std::to_string(options.budget_runs));
    if (options.refine_runs < 1) throw std::invalid_argument("refine_runs must be at least 1");
    if (options.max_effects < 1) throw std::invalid_argument("max_effects must be at least 1");
    Loop loop(lab, model, options, observer);
    return loop.run();
}

}  // namespace triax::diagnose
