// DEM forward model: ModelPoint -> TestScheme per confining pressure -> run_triaxial_test
// -> predicted curves (see dem_forward_model.hpp for the parameter mapping).
#include "engine/diagnose/dem_forward_model.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include "engine/diagnose/diagnosis.hpp"
#include "engine/protocol/triaxial_test.hpp"

namespace triax::diagnose {

namespace {

// Silent observer that forwards the diagnosis's cancellation into the DEM run.
class CancelOnly final : public protocol::RunObserver {
public:
    explicit CancelOnly(const DiagnoseObserver* o) : o_(o) {}
    bool cancel_requested() override { return o_ != nullptr && o_->cancelled(); }

private:
    const DiagnoseObserver* o_;
};

}  // namespace

DemForwardModel::DemForwardModel(const protocol::TestScheme& base, const LabDataset& lab, int threads,
                                 int max_particles, const DiagnoseObserver* cancel)
    : base_(base), cancel_(cancel) {
    base_.validate();
    if (threads > 0) base_.threads = threads;
    if (max_particles > 0) base_.max_particles = max_particles;
    bonded_ = base_.effects.moisture_bonding && base_.micro.bond_normal_strength_pa > 0.0;

    // One condition per confining pressure (2 % tolerance: lab cells drift a little).
    for (const auto& c : lab.curves) {
        if (c.confining_pa <= 0.0) continue;
        auto it = std::find_if(conditions_.begin(), conditions_.end(), [&](const Condition& k) {
            return std::abs(k.confining_pa - c.confining_pa) <= 0.02 * c.confining_pa;
        });
        if (it == conditions_.end()) {
            conditions_.push_back({c.confining_pa, false, base_.loading.stress_levels, base_.loading.stage_durations_s});
            it = conditions_.end() - 1;
        }
        if (c.kind != CurveKind::Creep || c.stage < 1) continue;
        it->creep = true;
        creep_in_lab_ = true;
        const auto k = static_cast<std::size_t>(c.stage);
        if (it->stress_levels.size() < k) it->stress_levels.resize(k, it->stress_levels.empty() ? 0.8 : it->stress_levels.back());
        if (it->durations_s.size() < k) it->durations_s.resize(k, it->durations_s.empty() ? 14400.0 : it->durations_s.back());
        if (c.stress_level > 0.0) it->stress_levels[k - 1] = c.stress_level;
        if (!c.time_s.empty()) {
            // Run a little past the last reading so interpolation never has to extrapolate.
            const double last = *std::max_element(c.time_s.begin(), c.time_s.end());
            it->durations_s[k - 1] = std::max(60.0, 1.02 * last);
        }
    }
    if (conditions_.empty())
        conditions_.push_back({base_.loading.confining_pressure_pa, false, base_.loading.stress_levels,
                               base_.loading.stage_durations_s});
    for (auto& k : conditions_) {
        // Stages run in order on one specimen: keep only as many as the lab reports.
        int last_stage = 0;
        for (const auto& c : lab.curves)
            if (c.kind == CurveKind::Creep && std::abs(c.confining_pa - k.confining_pa) <= 0.02 * k.confining_pa)
                last_stage = std::max(last_stage, c.stage);
        if (k.creep) {
            k.stress_levels.resize(static_cast<std::size_t>(last_stage));
            k.durations_s.resize(static_cast<std::size_t>(last_stage));
        }
    }
}

bool DemForwardModel::includes(Effect e) const {
    const auto& fx = base_.effects;
    switch (e) {
        case Effect::RollingResistance: return fx.rolling_resistance || base_.micro.rolling_friction > 0.0;
        // Crushable grains in the scheme (the paper-group presets): breakage is part of the
        // base model there.
        case Effect::BondDegradation: return base_.micro.crushing_strength_pa > 0.0;
        case Effect::ContactCreepViscosity: return fx.contact_creep_viscosity;
        case Effect::MoistureBonding: return fx.moisture_bonding;
        case Effect::SeatingError: return fx.seating_error;
        case Effect::MembraneCompliance: return fx.membrane_compliance;
    }
    return false;
}

std::vector<ParameterSpec> DemForwardModel::base_parameters() const {
    const auto& m = base_.micro;
    std::vector<ParameterSpec> p{
        {"contact_normal_modulus", "Pa", 0.2 * m.normal_modulus_pa, 5.0 * m.normal_modulus_pa, m.normal_modulus_pa, true},
        // Physical prior: inter-particle friction of mineral grains is about 0.1-0.7 (quartz
        // ~0.5 wet to ~0.7 rough); beyond it a fit is mimicking shape/interlocking with
        // friction (measured: the base fit ran to mu = 0.94 on data with hidden rolling
        // resistance, docs/diagnosis.md), which hides the effect the loop must find.
        {"friction", "-", 0.1, 0.7, std::clamp(m.friction, 0.1, 0.7), false}};
    if (bonded_)
        // Prior: within a factor 3 of the scheme's moisture relation either way (the
        // relation itself spans x0.62..x1 over the paper's moisture range). Wider, the base
        // fit mimics hidden rolling resistance with cementation: measured at 100 kPa on the
        // CI specimen, bonds x10 raise q at 0.5 % strain from 152 to 300 kPa, as much as
        // mu_r 0.25 does (x3: 186 kPa); the fit ran to x12 at 0.05..20 and to the bound at
        // 0.1..10 (docs/diagnosis.md section 8). A bound reached is stated in the verdict.
        p.push_back({"bond_strength_scale", "-", 1.0 / 3.0, 3.0, 1.0, true});
    if (base_.effects.contact_creep_viscosity && creep_in_lab_)
        p.push_back({"creep_slip_rate_scale", "-", 0.01, 100.0, 1.0, true});
    return p;
}

std::vector<ParameterSpec> DemForwardModel::effect_parameters(Effect e) const {
    if (includes(e)) return {};
    switch (e) {
        case Effect::RollingResistance: return {{"rolling_friction", "-", 0.0, 0.5, 0.1, false, true}};
        case Effect::BondDegradation: {
            // Grain crushing (engine/contact/grain_crushing.hpp) as a crushability
            // x = sigma_ref / sigma0 (sigma_ref = 0.6 MPa, the presets' grain of sessions 8-11): 0 = unbreakable
            // grains (the model without the effect, so base runs seed the fit), 1 = the
            // presets' slaking-mudstone grains, 2 = sigma0 0.3 MPa. Linear in x: a grain's
            // crushing force is proportional to 1/x. It acts in shear (contraction growing
            // with sigma3) and in the creep holds (creep slip shifts load onto crushable
            // contacts). Measured on the reduced specimens: docs/diagnosis.md section 8.7.
            std::vector<ParameterSpec> p{{"grain_crushability", "-", 0.0, kCrushabilityMax, 1.0, false, true}};
            // Bond damage under load (stress corrosion of the bonds in the creep holds,
            // bond_corrosion_scale = 1 + extra): only creep curves of a bonded specimen
            // can see it; off at 0 as well.
            if (creep_in_lab_ && bonded_ && !base_.effects.accelerated_bond_corrosion)
                p.push_back({"extra_bond_damage_rate", "-", 0.0, 9.0, 1.0, false, true});
            return p;
        }
        case Effect::ContactCreepViscosity:
            // Without lab creep curves the mechanism cannot be seen: do not propose it.
            if (!creep_in_lab_) return {};
            return {{"viscosity_scale", "-", 0.01, 100.0, 1.0, true}};
        case Effect::MoistureBonding: return {{"moisture_bond_strength_scale", "-", 0.05, 20.0, 1.0, true}};
        default: return {};
    }
}

protocol::TestScheme DemForwardModel::scheme_for(const ModelPoint& point, double confining_pa) const {
    const auto specs = base_parameters();
    if (point.base.size() != specs.size())
        throw std::invalid_argument("DEM forward model takes " + std::to_string(specs.size()) + " base parameters, got " +
                                    std::to_string(point.base.size()));
    protocol::TestScheme s = base_;
    std::size_t at = 0;
    const double ratio = base_.micro.shear_modulus_pa / base_.micro.normal_modulus_pa;
    s.micro.normal_modulus_pa = point.base[at++];
    s.micro.shear_modulus_pa = ratio * s.micro.normal_modulus_pa;
    s.micro.friction = point.base[at++];
    if (bonded_) {
        const double k = point.base[at++];
        s.micro.bond_normal_strength_pa *= k;
        s.micro.bond_shear_strength_pa *= k;
    }
    if (base_.effects.contact_creep_viscosity && creep_in_lab_) s.creep.slip_rate_a_m_s *= point.base[at++];
    for (const auto& [e, v] : point.effects) {
        if (v.empty()) throw std::invalid_argument("effect '" + std::string(effect_name(e)) + "' given no parameter");
        switch (e) {
            case Effect::RollingResistance:
                s.effects.rolling_resistance = true;
                s.effects.rolling_friction = v[0];
                s.micro.rolling_friction = v[0];
                break;
            case Effect::BondDegradation:
                if (v[0] < 0.0) throw std::invalid_argument("grain_crushability must be >= 0");
                s.micro.crushing_strength_pa = v[0] > 0.0 ? kCrushabilityReferencePa / v[0] : 0.0;
                if (v.size() > 1 && v[1] > 0.0) {
                    s.effects.accelerated_bond_corrosion = true;
                    s.effects.bond_corrosion_scale = 1.0 + v[1];
                }
                break;
            case Effect::ContactCreepViscosity:
                s.effects.contact_creep_viscosity = true;
                s.effects.viscosity_scale = v[0];
                break;
            case Effect::MoistureBonding:
                s.effects.moisture_bonding = true;
                s.micro.bond_normal_strength_pa *= v[0];
                s.micro.bond_shear_strength_pa *= v[0];
                break;
            default:
                throw std::invalid_argument("DEM forward model: '" + std::string(effect_name(e)) +
                                            "' is a test artefact, applied by the diagnosis");
        }
    }
    s.loading.confining_pressure_pa = confining_pa;
    return s;
}

LabDataset DemForwardModel::simulate(const ModelPoint& point, std::uint64_t seed) const {
    LabDataset out;
    out.name = base_.name;
    for (const auto& k : conditions_) {
        protocol::TestScheme s = scheme_for(point, k.confining_pa);
        s.seed = seed;
        if (k.creep) {
            s.loading.stress_levels = k.stress_levels;
            s.loading.stage_durations_s = k.durations_s;
        }
        CancelOnly observer(cancel_);
        const auto r = protocol::run_triaxial_test(s, observer, k.creep ? protocol::Phase::Creep : protocol::Phase::Shear);
        if (r.cancelled) throw DiagnosisCancelled{};
        if (!r.converged && r.shear.empty())
            throw std::runtime_error("DEM run at " + std::to_string(k.confining_pa / 1e3) + " kPa did not shear");
        LabCurve sh;
        sh.kind = CurveKind::Shear;
        sh.confining_pa = k.confining_pa;
        // The protocol records from the first shear chunk on; the start of shear (isotropic
        // state: no strain, no deviator, no volume change) is part of the curve, and lab
        // readings taken before the first chunk must not fall outside the model's range.
        if (r.shear.empty() || r.shear.front().axial_strain > 0.0) {
            sh.axial_strain.push_back(0.0);
            sh.deviator_pa.push_back(0.0);
            sh.volumetric_strain.push_back(0.0);
        }
        for (const auto& p : r.shear) {
            sh.axial_strain.push_back(p.axial_strain);
            sh.deviator_pa.push_back(p.q_pa);
            sh.volumetric_strain.push_back(p.volumetric_strain);
        }
        out.curves.push_back(std::move(sh));
        for (const auto& st : r.creep_stages) {
            LabCurve c;
            c.kind = CurveKind::Creep;
            c.stage = st.stage;
            c.confining_pa = k.confining_pa;
            c.stress_level = st.stress_level;
            for (const auto& p : st.translated) {
                c.time_s.push_back(p.time_s);
                c.axial_strain.push_back(p.axial_strain);
                c.axial_deformation_m.push_back(p.axial_deformation_m);
            }
            out.curves.push_back(std::move(c));
        }
    }
    return out;
}

// Product entry point (declared in diagnosis.hpp).
DiagnosisReport run_diagnosis(const LabDataset& lab, const protocol::TestScheme& base, const DiagnoseOptions& options,
                              DiagnoseObserver& observer) {
    const DemForwardModel model(base, lab, options.threads_per_run, options.max_particles, &observer);
    return run_diagnosis(lab, model, options, observer);
}

}  // namespace triax::diagnose
