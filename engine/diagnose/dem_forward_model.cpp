// DEM forward model: ModelPoint -> TestScheme per confining pressure -> run_triaxial_test
// -> predicted curves (see dem_forward_model.hpp for the parameter mapping).
#include "engine/diagnose/dem_forward_model.hpp"

#include "engine/diagnose/curve_smoothing.hpp"
#include "engine/diagnose/packing_ensemble.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include "engine/diagnose/diagnosis.hpp"
#include "engine/diagnose/lab_macro.hpp"
#include "engine/diagnose/simulation_batch.hpp"
#include "engine/protocol/triaxial_test.hpp"

namespace triax::diagnose {

double creep_direct_effect_for(double strain_per_decade) {
    if (!(strain_per_decade > 0.0)) return kCreepRefA;
    const double a = kCreepRefA * std::pow(strain_per_decade / kCreepPerDecadeAtRef, 1.0 / kCreepPerDecadeExponent);
    return std::clamp(a, kCreepDirectEffectMin, kCreepDirectEffectMax);
}

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

DemForwardModel::DemForwardModel(const protocol::TestScheme& base, const LabDataset& lab, const DiagnoseOptions& options,
                                 const DiagnoseObserver* cancel)
    : DemForwardModel(base, lab, options.threads_per_run, options.max_particles, cancel, options.packings_per_run,
                      options.relative_density) {}

DemForwardModel::DemForwardModel(const protocol::TestScheme& base, const LabDataset& lab, int threads,
                                 int max_particles, const DiagnoseObserver* cancel, int packings,
                                 std::optional<double> relative_density)
    : scheme_(base), base_(base), cancel_(cancel), packings_(packings), relative_density_(relative_density) {
    scheme_.validate();
    if (packings < 1 || packings > 16) throw std::invalid_argument("packings per model run must be 1..16");
    if (relative_density && !(*relative_density >= 0.0 && *relative_density <= 1.0))
        throw std::invalid_argument("relative density must be 0..1 (0 = loosest, 1 = densest)");
    base_.specimen.target_porosity = kDiagnosisGenerationPorosity;
    if (relative_density) base_.specimen.compaction_friction_ratio = compaction_friction_for(*relative_density);
    if (threads > 0) base_.threads = threads;
    // The calibration specimen is the scheme's (max_particles > 0 caps its grains, never
    // above the scheme's own cap). A coarser membrane (D / 12) and a faster shear
    // (I = 1e-3) cut a run's particle-steps 3.4x
    // (bench/forward_run_cost) but raised the packing scatter of the CI rolling-resistance
    // case from 4.4 % to 11 %, and the effect was no longer named: not adopted
    // (docs/diagnosis.md, section 6).
    if (max_particles > 0)
        base_.max_particles = base_.max_particles > 0 ? std::min(base_.max_particles, max_particles) : max_particles;
    // No membrane lattice: sigma3 acts on the outermost grains. The bonded membrane's springs
    // add k eps_r / R of confinement (80 kPa at 10 % radial strain on a 50 mm specimen) and
    // kept the base above 40 deg at grain friction 0.05; a lab's latex membrane is the
    // membrane-compliance artefact (docs/diagnosis.md, section 6).
    base_.specimen.lateral_boundary = protocol::SpecimenSpec::LateralBoundary::GrainPressure;
    // The catalog's effects out of the base (dem_forward_model.hpp).
    auto& m = base_.micro;
    auto& fx = base_.effects;
    m.rolling_friction = 0.0;
    m.bond_rolling_friction = 0.0;
    m.crushing_strength_pa = 0.0;
    fx.accelerated_bond_corrosion = false;
    fx.bond_corrosion_scale = 1.0;
    fx.contact_creep_viscosity = false;
    fx.seating_error = false;
    fx.membrane_compliance = false;
    // Bonds as one base parameter: their strength in Pa, from 0, as the specimen has it (the
    // moisture relation would only rescale what the calibration sets).
    const double scheme_bond = std::max(m.bond_normal_strength_pa, m.bond_shear_strength_pa);
    bond_strength_max_pa_ = std::max(3.0 * scheme_bond, 300.0e3);
    const LabMacro macro = lab_macro(lab);
    double mean_q = 0.0;
    for (const auto& sh : macro.shear) mean_q += sh.q_peak_pa / static_cast<double>(macro.shear.size());
    // Bonds only where the lab's own envelope shows cohesion: an intercept c' of its peak
    // Mohr-Coulomb envelope across its sigma3 values worth 5 % of q (one pressure: the
    // envelope runs through the origin). Otherwise the bond strength is held at 0, so that
    // cohesion the lab does not show cannot stand in for a missing strength (on a
    // cohesionless outside material a free bond strength took 85-457 kPa and absorbed the
    // strength rolling resistance brings: docs/diagnosis.md section 6). Without a lab shear
    // curve the envelope is unknown and the scheme's bonds decide.
    lab_cohesion_pa_ = macro.peak_cohesion_pa;
    // The creep effect starts from the lab's creep per decade at its highest stress level.
    const CreepMacro* top = nullptr;
    for (const auto& cm : macro.creep)
        if (cm.strain_per_decade > 0.0 && (!top || cm.stress_level > top->stress_level ||
                                           (cm.stress_level == top->stress_level && cm.stage > top->stage)))
            top = &cm;
    if (top) creep_seed_a_ = creep_direct_effect_for(top->strain_per_decade);
    bonds_calibrated_ = macro.shear.empty() ? scheme_bond > 0.0 : macro.peak_cohesion_pa > 0.05 * mean_q;
    bond_strength_nominal_pa_ =
        bonds_calibrated_ ? std::min(scheme_bond > 0.0 ? scheme_bond : 100.0e3, bond_strength_max_pa_) : 0.0;
    // Dense start when the lab's curves peak early and soften (q at the last reading under
    // 85 % of the peak, reached before half the test), else loose.
    int softening = 0;
    for (const auto& sh : macro.shear)
        if (sh.q_peak_pa > 0.0 && sh.q_last_pa < 0.85 * sh.q_peak_pa && sh.strain_at_peak < 0.5 * sh.last_strain) ++softening;
    compaction_nominal_ = 2 * softening > static_cast<int>(macro.shear.size()) ? 0.25 : 1.0;
    fx.moisture_bonding = false;

    // One condition per confining pressure (2 % tolerance: lab cells drift a little).
    for (const auto& c : lab.curves) {
        if (c.confining_pa <= 0.0) continue;
        auto it = std::find_if(conditions_.begin(), conditions_.end(), [&](const Condition& k) {
            return std::abs(k.confining_pa - c.confining_pa) <= 0.02 * c.confining_pa;
        });
        if (it == conditions_.end()) {
            conditions_.push_back({c.confining_pa, false, base_.loading.stress_levels, base_.loading.stage_durations_s, 0.0});
            it = conditions_.end() - 1;
        }
        if (c.kind == CurveKind::Shear && !c.axial_strain.empty()) it->lab_shear = true;
        if (c.kind == CurveKind::Shear && !c.axial_strain.empty())
            it->max_axial_strain = std::max(it->max_axial_strain, *std::max_element(c.axial_strain.begin(), c.axial_strain.end()));
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
                               base_.loading.stage_durations_s, 0.0});
    for (auto& k : conditions_) {
        // The shear runs 2 % past the lab's last reading (at least 0.5 % strain); a creep test
        // without a lab shear curve at its pressure keeps the scheme's end for its q_f.
        k.max_axial_strain = k.max_axial_strain > 0.0 ? std::clamp(1.02 * k.max_axial_strain, 0.005, 0.4)
                                                      : base_.loading.max_axial_strain;
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

std::string DemForwardModel::lab_cohesion_text() const {
    return "c' = " + std::to_string(static_cast<long>(std::lround(lab_cohesion_pa_ / 1e3))) + " kPa";
}

bool DemForwardModel::includes(Effect e) const {
    // Only the artefacts and moisture bonding can be in the base: the others were taken out.
    switch (e) {
        case Effect::MoistureBonding: return bonds_calibrated_;
        default: return false;
    }
}

std::string DemForwardModel::not_offered_reason(Effect e) const {
    switch (e) {
        case Effect::MoistureBonding:
            if (!bonds_calibrated_)
                return "the lab's peak Mohr-Coulomb envelope shows no cohesion (" + lab_cohesion_text() +
                       ", under 5 % of q): no bonds to add";
            return "the base calibrates the bond strength from 0 (cohesionless) upwards, which is what moisture "
                   "bonding would add";
        case Effect::ContactCreepViscosity:
            return creep_in_lab_ ? std::string{} : "no creep curve in the data: time-dependent slip cannot be seen";
        default: return {};
    }
}

std::vector<HeldParameter> DemForwardModel::held_fixed() const {
    const auto& m = scheme_.micro;
    std::vector<HeldParameter> h{
        {"shear_to_normal_modulus_ratio", "-", m.shear_modulus_pa / m.normal_modulus_pa, "the scheme's ratio (E_s / E_n)"},
        {"local_damping", "-", m.local_damping, "quasi-static runs: damping does not set the response"},
        {"wall_friction", "-", m.wall_friction, "rough platens"},
        {"membrane_stiffness", "N/m", 0.0,
         "no membrane in the base: sigma3 acts on the outermost grains (a bonded lattice adds confinement); a lab "
         "membrane's stiffness is the membrane-compliance artefact"},
        {"bond_friction", "-", m.bond_friction, "the bonds' Mohr-Coulomb friction"},
        {"max_particles", "-", static_cast<double>(base_.max_particles), "the calibration specimen's grain cap (0: the scheme's gradation)"},
    };
    if (!bonds_calibrated_)
        h.push_back({"bond_strength", "Pa", 0.0,
                     "cohesionless: the lab's peak Mohr-Coulomb envelope has no cohesion intercept worth 5 % of q (" +
                         lab_cohesion_text() + ")"});
    h.push_back({"generation_porosity", "-", kDiagnosisGenerationPorosity,
                 "the packing is grown loose; the compaction friction gives it its density"});
    if (relative_density_)
        h.push_back({"compaction_friction_ratio", "-", base_.specimen.compaction_friction_ratio,
                     "from the lab's relative density D_r = " + std::to_string(100.0 * *relative_density_) +
                         " % (1 - D_r: between the model's loosest and densest packings)"});
    if (m.bond_rolling_friction > 0.0)
        h.push_back({"bond_rolling_friction", "-", 0.0,
                     "the scheme's cement neck (" + std::to_string(m.bond_rolling_friction) +
                         ") is off in the base: rolling resistance is tested as an effect"});
    if (m.crushing_strength_pa > 0.0)
        h.push_back({"crushing_strength", "Pa", 0.0,
                     "the scheme's crushable grains (" + std::to_string(m.crushing_strength_pa / 1e6) +
                         " MPa) are off in the base: grain breakage is tested as an effect"});
    if (creep_in_lab_) {
        h.push_back({"critical_slip", "m", scheme_.creep.critical_slip_m,
                     "the creep law's critical slip D_c; the creep effect fits its rate sensitivity a"});
        h.push_back({"state_exponent_m", "-", scheme_.creep.state_exponent_m, "the creep law's decay t^-m of the creep rate"});
        h.push_back({"renewed_age", "s", scheme_.creep.renewed_age_s, "the state of a contact renewed by a stage's loading"});
        h.push_back({"bond_corrosion_rate_b1", "1/s", scheme_.creep.bond_corrosion_rate_b1_per_s, "the bonds' stress corrosion rate"});
    }
    return h;
}

std::vector<ParameterSpec> DemForwardModel::base_parameters() const {
    const auto& m = scheme_.micro;
    std::vector<ParameterSpec> specs{
        // Two decades around the scheme's modulus: a fill's small-strain stiffness spans that.
        {"contact_normal_modulus", "Pa", 0.1 * m.normal_modulus_pa, 10.0 * m.normal_modulus_pa, m.normal_modulus_pa, true},
        // Friction of mineral contacts and of rough, angular grains that a sphere must mimic.
        {"friction", "-", 0.05, 1.0, std::clamp(m.friction, 0.05, 1.0), false},
    };
    // Cohesion from cementation or suction, from none up: only where the lab shows it.
    if (bonds_calibrated_) specs.push_back({"bond_strength", "Pa", 0.0, bond_strength_max_pa_, bond_strength_nominal_pa_, false, true});
    // The packing's density by the friction it is consolidated at: frictionless packs dense
    // (an early peak, dilation), the grains' own friction leaves it loose (contraction,
    // hardening to late strains, as a weak fill does; docs/diagnosis.md section 6). Held
    // when the lab states its relative density.
    if (!relative_density_) specs.push_back({"compaction_friction_ratio", "-", 0.0, 1.0, compaction_nominal_, false});
    return specs;
}

std::vector<ParameterSpec> DemForwardModel::effect_parameters(Effect e) const {
    if (includes(e)) return {};
    switch (e) {
        case Effect::RollingResistance: return {{"rolling_friction", "-", 0.0, 0.5, 0.1, false, true}};
        case Effect::BondDegradation: {
            // Grain crushing (engine/contact/grain_crushing.hpp) as a crushability
            // x = sigma_ref / sigma0 (sigma_ref = 0.6 MPa): 0 = unbreakable grains (the
            // model without the effect, so base runs seed the fit), 2 = sigma0 0.3 MPa.
            // Linear in x: a grain's crushing force is proportional to 1/x. It acts in shear
            // (contraction growing with sigma3) and in the creep holds (creep slip shifts
            // load onto crushable contacts).
            std::vector<ParameterSpec> p{{"grain_crushability", "-", 0.0, kCrushabilityMax, 1.0, false, true}};
            // Bond damage under load (stress corrosion of the bonds in the creep holds,
            // bond_corrosion_scale = 1 + extra): only creep curves of a bonded specimen
            // can see it; off at 0 as well.
            if (creep_in_lab_)
                p.push_back({"extra_bond_damage_rate", "-", 0.0, 9.0, 1.0, false, true});
            return p;
        }
        case Effect::ContactCreepViscosity:
            // Without lab creep curves the mechanism cannot be seen: do not propose it.
            if (!creep_in_lab_) return {};
            // Rate-and-state creep at the contacts, switched on with its rate sensitivity a
            // (0 = off, the base without creep): a stage's creep per decade of time grows
            // with a (bench/README.md, "Rate-and-state contact creep"); the nominal is read off
            // the lab's own creep per decade (creep_seed_a_).
            return {{"direct_effect_a", "-", 0.0, kCreepDirectEffectMax, creep_seed_a_, false, true}};
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
    s.micro.bond_normal_strength_pa = s.micro.bond_shear_strength_pa = bonds_calibrated_ ? std::max(0.0, point.base[at++]) : 0.0;
    if (!relative_density_) s.specimen.compaction_friction_ratio = point.base[at++];
    for (const auto& [e, v] : point.effects) {
        if (v.empty()) throw std::invalid_argument("effect '" + std::string(effect_name(e)) + "' given no parameter");
        switch (e) {
            case Effect::RollingResistance:
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
                if (v[0] < 0.0) throw std::invalid_argument("direct_effect_a must be >= 0");
                // 0 is the base without creep (the law off), so base runs seed the fit.
                s.effects.contact_creep_viscosity = v[0] > 0.0;
                s.effects.viscosity_scale = 1.0;
                if (v[0] > 0.0) s.creep.direct_effect_a = std::max(kCreepDirectEffectMin, v[0]);
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
    if (packings_ == 1) return simulate_packing(point, seed);
    std::vector<LabDataset> each;
    for (int j = 0; j < packings_; ++j)
        each.push_back(simulate_packing(point, seed + static_cast<std::uint64_t>(j) * kPackingSeedStride));
    return mean_over_packings(each);
}

std::vector<DemForwardModel::EngineRun> DemForwardModel::engine_runs(const ModelPoint& point) const {
    std::vector<EngineRun> out;
    for (const auto& k : conditions_) {
        protocol::TestScheme s = scheme_for(point, k.confining_pa);
        if (k.creep) {
            s.loading.stress_levels = k.stress_levels;
            s.loading.stage_durations_s = k.durations_s;
        }
        // The shear covers the lab's readings: no failure stop inside them; q_f of the creep
        // stages is then the peak over the lab's strain range, as the lab reads it.
        if (!k.creep || k.lab_shear) {
            s.loading.max_axial_strain = k.max_axial_strain;
            s.loading.stop_at_softening = false;
        }
        out.push_back({std::move(s), k.creep ? protocol::Phase::Creep : protocol::Phase::Shear});
    }
    return out;
}

LabDataset DemForwardModel::simulate_packing(const ModelPoint& point, std::uint64_t seed) const {
    LabDataset out;
    out.name = base_.name;
    const auto runs = engine_runs(point);
    for (std::size_t i = 0; i < conditions_.size(); ++i) {
        const Condition& k = conditions_[i];
        protocol::TestScheme s = runs[i].scheme;
        s.seed = seed;
        CancelOnly observer(cancel_);
        const auto r = protocol::run_triaxial_test(s, observer, runs[i].last_phase);
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
        // One packing's slip events averaged out, as a lab specimen's many grains do.
        sh.deviator_pa = smooth_over_relative_strain(sh.axial_strain, sh.deviator_pa);
        sh.volumetric_strain = smooth_over_relative_strain(sh.axial_strain, sh.volumetric_strain);
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
    ThreadSimulationBatch batch(options.concurrency);
    return run_diagnosis(lab, base, options, observer, batch);
}

DiagnosisReport run_diagnosis(const LabDataset& lab, const protocol::TestScheme& base, const DiagnoseOptions& options,
                              DiagnoseObserver& observer, SimulationBatch& batch) {
    const DemForwardModel model(base, lab, options, &observer);
    return run_diagnosis(lab, model, options, observer, batch);
}

}  // namespace triax::diagnose
