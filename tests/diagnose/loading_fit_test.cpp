// A base with no law in physical time is fitted to the loading readings only (shear q,
// volumetric, instant strains; docs/diagnosis.md section 2). The stand-in mimics the DEM
// base: its creep holds creep more the nearer the specimen is to failure (a weaker friction
// angle), and it has no creep parameter of its own. The lab's creep is larger than the base
// can give at the lab's strength (contact creep hidden in it). Fitted to every reading, the
// base weakens to buy creep; fitted to the loading readings, it keeps the lab's strength.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "analytic_triaxial_model.hpp"
#include "engine/diagnose/diagnosis.hpp"
#include "synthetic_lab.hpp"

using namespace triax::diagnose;
using namespace triax::diagnose::testing;

namespace {

class NearFailureCreepModel final : public ForwardModel {
public:
    explicit NearFailureCreepModel(bool acts_in_time) : acts_in_time_(acts_in_time) {}
    // The stand-in's base without its creep coefficient: E, friction and dilatancy angles.
    std::vector<ParameterSpec> base_parameters() const override {
        auto p = inner_.base_parameters();
        p.pop_back();
        return p;
    }
    std::vector<ParameterSpec> effect_parameters(Effect e) const override {
        return e == Effect::ContactCreepViscosity ? inner_.effect_parameters(e) : std::vector<ParameterSpec>{};
    }
    bool base_acts_in_time() const override { return acts_in_time_; }
    LabDataset simulate(const ModelPoint& p, std::uint64_t seed) const override {
        ModelPoint full = p;
        // Creep per log-time grows e-fold per 2 deg of friction lost below 36 deg.
        full.base.push_back(1e-4 * std::exp((36.0 - p.base.at(1)) / 2.0));
        return inner_.simulate(full, seed);
    }

private:
    AnalyticTriaxialModel inner_;
    bool acts_in_time_;
};

double calibrated_friction_angle(bool base_acts_in_time) {
    const NearFailureCreepModel model(base_acts_in_time);
    // Truth: 36 deg with contact creep of 0.6 % x S^2 that the base cannot give.
    const ModelPoint truth{{30e6, 36.0, 10.0}, {{Effect::ContactCreepViscosity, {0.006, 3000.0}}}};
    const LabDataset lab = make_synthetic_lab(model, truth, SyntheticLabOptions{});
    DiagnoseOptions opt = analytic_method_options();
    opt.max_effects = 1;
    opt.max_candidates = 1;
    DiagnoseObserver quiet;
    const DiagnosisReport r = run_diagnosis(lab, model, opt, quiet);
    const auto it = std::find_if(r.base_parameters.begin(), r.base_parameters.end(),
                                 [](const FittedParameter& f) { return f.name == "friction_angle"; });
    REQUIRE(it != r.base_parameters.end());
    return it->value;
}

}  // namespace

TEST_CASE("a base with no law in time keeps the lab's strength instead of buying creep by weakening", "[diagnose][loading]") {
    const double loading_only = calibrated_friction_angle(false);
    const double every_reading = calibrated_friction_angle(true);
    INFO("friction angle fitted on the loading readings " << loading_only << " deg, on every reading " << every_reading
                                                          << " deg (truth 36)");
    CHECK(std::abs(loading_only - 36.0) < 1.0);
    // The mechanism the rule removes: fitted to the creep curves too, the base weakens.
    CHECK(every_reading < loading_only - 1.5);
}
