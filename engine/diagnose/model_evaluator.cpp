// Cached, batched, retried forward runs and their residuals (see model_evaluator.hpp).
#include "engine/diagnose/model_evaluator.hpp"

#include "engine/diagnose/fit_weights.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "engine/diagnose/diagnosis.hpp"
#include "engine/diagnose/model_selection.hpp"
#include "engine/diagnose/test_artefacts.hpp"

namespace triax::diagnose {

ModelEvaluator::ModelEvaluator(const LabDataset& lab, const ForwardModel& model, SimulationBatch& batch,
                               std::uint64_t seed)
    : model_(model), batch_(batch), seed_(seed), layout_(residual_layout(lab)), ranges_(series_ranges(layout_)),
      base_specs_(model.base_parameters()) {
    if (base_specs_.empty()) throw std::invalid_argument("forward model has no base parameter to calibrate");
    for (Effect e : kAllEffects) {
        std::string why = model.not_offered_reason(e);
        if (model.includes(e)) {
            not_offered_.emplace_back(e, why.empty() ? "already part of the base model" : why);
            continue;
        }
        auto specs = is_test_artefact(e) ? artefact_parameters(e) : model.effect_parameters(e);
        if (!specs.empty()) effect_specs_[e] = std::move(specs);
        else if (!is_test_artefact(e)) not_offered_.emplace_back(e, why.empty() ? "the model cannot show it on these data" : why);
    }
}

std::vector<ParameterSpec> ModelEvaluator::specs_of(const Variant& v) const {
    auto s = base_specs_;
    for (Effect e : v.effects) s.insert(s.end(), effect_specs_.at(e).begin(), effect_specs_.at(e).end());
    return s;
}

UnitPoint ModelEvaluator::nominal_unit(const std::vector<ParameterSpec>& specs) const {
    UnitPoint u(specs.size());
    for (std::size_t j = 0; j < specs.size(); ++j) u[j] = to_unit(specs[j], specs[j].nominal);
    return u;
}

UnitPoint ModelEvaluator::extended(UnitPoint u, Effect e) const {
    const UnitPoint extra = nominal_unit(effect_specs_.at(e));
    u.insert(u.end(), extra.begin(), extra.end());
    return u;
}

UnitPoint ModelEvaluator::project(const Variant& from, const UnitPoint& u, const Variant& to) const {
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

std::vector<std::pair<std::size_t, Effect>> ModelEvaluator::artefact_coordinates(const Variant& v) const {
    std::vector<std::pair<std::size_t, Effect>> out;
    std::size_t at = base_specs_.size();
    for (Effect e : v.effects) {
        if (is_test_artefact(e)) out.emplace_back(at, e);
        at += effect_specs_.at(e).size();
    }
    return out;
}

// The engine's input at u: base values and the physical effects that are on. An effect at
// its "off" bound is the model without it (same run, same cache key).
ModelPoint ModelEvaluator::physical_point(const Variant& v, const UnitPoint& u, std::vector<double>& key) const {
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
        const auto& sp = effect_specs_.at(e);
        bool off = true;
        for (std::size_t q = 0; q < m; ++q) off = off && sp[q].lower_is_off && p[q] <= sp[q].lower;
        if (!off) point.effects.emplace_back(e, std::move(p));
    }
    std::sort(point.effects.begin(), point.effects.end());
    key = point.base;
    for (const auto& [e, p] : point.effects) {
        key.push_back(1000.0 + static_cast<double>(e));
        key.insert(key.end(), p.begin(), p.end());
    }
    return point;
}

void ModelEvaluator::run_missing(const std::vector<ModelPoint>& points, const std::vector<std::vector<double>>& keys) {
    std::vector<SimulationRequest> requests;
    std::vector<std::size_t> which;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (std::size_t i = 0; i < points.size(); ++i) {
            if (cache_.count(keys[i]) || failed_.count(keys[i])) continue;
            bool dup = false;
            for (std::size_t k : which) dup = dup || keys[k] == keys[i];
            if (dup) continue;
            which.push_back(i);
            requests.push_back({points[i], seed_});
        }
    }
    if (requests.empty()) return;
    auto out = batch_.run(model_, requests, [this](std::size_t) { count_run(); });
    // One retry per failed run, on another packing: a particle escaping the box or a shear
    // that never starts is a property of that packing at those parameters, not of the
    // parameters alone (seen on 150-grain specimens of preset B).
    std::vector<SimulationRequest> again;
    std::vector<std::size_t> again_at;
    for (std::size_t r = 0; r < out.size(); ++r) {
        if (out[r].ok) continue;
        // A cancelled run reports the cancellation's message (SimulationBatch keeps what()).
        if (out[r].error == DiagnosisCancelled{}.what()) throw DiagnosisCancelled{};
        again.push_back({requests[r].point, requests[r].seed + kRetrySeedOffset});
        again_at.push_back(r);
    }
    if (!again.empty()) {
        retried_ += static_cast<int>(again.size());
        const auto second = batch_.run(model_, again, [this](std::size_t) { count_run(); });
        for (std::size_t k = 0; k < second.size(); ++k) {
            if (second[k].ok) out[again_at[k]] = second[k];
            else if (second[k].error == DiagnosisCancelled{}.what()) throw DiagnosisCancelled{};
            else out[again_at[k]].error += "; retry on another packing: " + second[k].error;
        }
    }
    std::lock_guard<std::mutex> lock(mutex_);
    for (std::size_t r = 0; r < out.size(); ++r) {
        const auto& key = keys[which[r]];
        if (out[r].ok) {
            cache_.emplace(key, std::move(out[r].curves));
        } else {
            failed_[key] = true;
            ++failures_;
            if (messages_.size() < 5 && std::find(messages_.begin(), messages_.end(), out[r].error) == messages_.end())
                messages_.push_back(out[r].error);
        }
    }
}

std::vector<std::string> ModelEvaluator::failure_messages() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return messages_;
}

std::vector<double> ModelEvaluator::with_artefacts(const Variant& v, const LabDataset& physical, const UnitPoint& u) const {
    LabDataset d = physical;
    for (const auto& [j, e] : artefact_coordinates(v)) apply_test_artefact(d, e, {to_parameter(effect_specs_.at(e)[0], u[j])}, model_.specimen_height_m());
    auto r = normalised_residual(layout_, d);
    if (weights_.size() == r.size())
        for (std::size_t i = 0; i < r.size(); ++i) r[i] *= weights_[i];
    return r;
}

std::vector<double> ModelEvaluator::unweighted(std::vector<double> r) const {
    return diagnose::unweighted(std::move(r), weights_);
}

double ModelEvaluator::unreached_sum_of_squares() const {
    if (weights_.size() != readings()) return kUnreachedPenalty * kUnreachedPenalty * static_cast<double>(readings());
    double ss = 0.0;
    for (double w : weights_) ss += kUnreachedPenalty * kUnreachedPenalty * w * w;
    return ss;
}

// Artefact coordinates of u set to their optimum for this run: coarse grid, then golden
// section; two sweeps when there are two artefacts.
std::vector<double> ModelEvaluator::polished(const Variant& v, const LabDataset& physical, UnitPoint& u) const {
    const auto coords = artefact_coordinates(v);
    if (coords.empty()) return with_artefacts(v, physical, u);
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

std::vector<std::vector<double>> ModelEvaluator::residuals(const Variant& v, std::vector<UnitPoint>& batch, bool polish) {
    std::vector<ModelPoint> points(batch.size());
    std::vector<std::vector<double>> keys(batch.size());
    for (std::size_t i = 0; i < batch.size(); ++i) points[i] = physical_point(v, batch[i], keys[i]);
    run_missing(points, keys);
    std::vector<std::vector<double>> out(batch.size());
    for (std::size_t i = 0; i < batch.size(); ++i) {
        const LabDataset* physical = nullptr;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            auto it = cache_.find(keys[i]);
            if (it != cache_.end()) physical = &it->second;  // std::map nodes are stable
        }
        if (!physical) continue;  // failed twice: empty residual
        out[i] = polish ? polished(v, *physical, batch[i]) : with_artefacts(v, *physical, batch[i]);
    }
    return out;
}

LabDataset ModelEvaluator::curves(const Variant& v, const UnitPoint& u) {
    std::vector<double> key;
    const ModelPoint p = physical_point(v, u, key);
    run_missing({p}, {key});
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = cache_.find(key);
    if (it == cache_.end()) return {};
    LabDataset d = it->second;
    for (const auto& [j, e] : artefact_coordinates(v)) apply_test_artefact(d, e, {to_parameter(effect_specs_.at(e)[0], u[j])}, model_.specimen_height_m());
    return d;
}

std::vector<std::vector<double>> ModelEvaluator::replicates(const Variant& v, const UnitPoint& u,
                                                           const std::vector<std::uint64_t>& seeds) {
    std::vector<double> key;
    const ModelPoint p = physical_point(v, u, key);
    std::vector<SimulationRequest> requests;
    for (std::uint64_t s : seeds) requests.push_back({p, s});
    const auto out = batch_.run(model_, requests, [this](std::size_t) { count_run(); });
    std::vector<std::vector<double>> r(out.size());
    for (std::size_t i = 0; i < out.size(); ++i) {
        if (!out[i].ok && out[i].error == DiagnosisCancelled{}.what()) throw DiagnosisCancelled{};
        if (out[i].ok) r[i] = with_artefacts(v, out[i].curves, u);
    }
    return r;
}

}  // namespace triax::diagnose
