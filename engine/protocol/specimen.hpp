#pragma once
// The triaxial specimen as a DEM model: soil spheres inside the bonded-particle membrane
// between two rigid platens (plane walls), and the measurements on it. Axis z, centre at
// the origin; groups: soil 0, membrane 1, platens 2. SI units, compression positive.
#include <memory>
#include <random>

#include "engine/boundary/membrane.hpp"
#include "engine/contact/grain_crushing.hpp"
#include "engine/core/world.hpp"
#include "engine/protocol/test_scheme.hpp"

namespace triax::protocol {

constexpr int kSoilGroup = 0;
constexpr int kMembraneGroup = 1;
constexpr int kPlatenGroup = 2;

class Specimen {
public:
    // Generates the soil at the target porosity by radius expansion inside the (held)
    // membrane: radii drawn from the gradation fill (1 - n) of the specimen volume, are
    // placed at 60 % size without overlap (seeded), then grown to full size in steps with
    // frictionless contacts, and relaxed to equilibrium. Deterministic for scheme.seed.
    explicit Specimen(const TestScheme& scheme);
    // A deep copy (world and membrane): a second test on the same consolidated specimen
    // without generating and consolidating it again.
    Specimen(const Specimen& other);
    Specimen& operator=(const Specimen&) = delete;

    World& world() { return world_; }
    const World& world() const { return world_; }
    boundary::Membrane& membrane() { return *membrane_; }

    // Switches to the test's contact laws (friction on; bond strength per moisture).
    void install_test_laws();
    // Makes the grain contacts crushable (if micro.crushing_strength_pa > 0), on the
    // consolidated fabric: the overlaps the radius expansion locks in are a packing
    // device, not loads, and would crush into a denser specimen (docs/protocol.md).
    void enable_crushing();
    // Installs soil-soil contact bonds on the current contacts (strength per contact
    // = strength (Pa) x pi r_min^2 of the pair, scaled by the moisture relation).
    long install_soil_bonds();

    // Cycles n steps, refreshing the membrane follower forces every few steps; crushable
    // contacts are return-mapped after every such chunk.
    void cycle(long n, double confining_pa);
    // Crushing events (contacts x passes) since enable_crushing().
    long crushing_events() const { return crushing_events_; }
    // Grain i's crushing force F_c (N); empty when crushing is off.
    const std::vector<double>& crushing_forces() const { return crush_force_; }
    // Static fatigue of crushable grains over a creep increment dt (grain_crushing.hpp):
    // grows each grain's damage at its present peak contact force and lowers its crushing
    // force to F_c (1 - D) for the return map of the next cycles. apply = false: dry run.
    // The drive (peak force or grain stress) and the life scale follow p (GrainFatigueParams).
    FatigueSummary advance_fatigue(double dt, const GrainFatigueParams& p, bool apply = true);
    // Instantaneous crushing (p.instant_life_s > 0): grains whose life at the present forces
    // is shorter than that fail now; returns how many (the caller relaxes and repeats).
    long fail_short_lived_grains(const GrainFatigueParams& p);
    // Grain i's life scale t0_i / t0 = (S_i / sigma0)^-2 (brittle lifetime law; used when
    // p.strength_spread), S_i = F_c,i / d_i^2; empty when crushing is off.
    const std::vector<double>& fatigue_life_scale() const { return fatigue_life_scale_; }
    // Grain i's fatigue damage D (empty when crushing is off).
    const std::vector<double>& fatigue_damage() const { return fatigue_damage_; }

    double top_z() const;
    double bottom_z() const;
    double height() const { return top_z() - bottom_z(); }
    double volume() const;                       // membrane-enclosed, m^3
    double axial_stress() const;                 // mean of both platens, Pa
    double top_stress() const;
    double solid_volume() const { return solid_volume_; }
    double porosity() const { return 1.0 - solid_volume_ / volume(); }
    double mean_diameter() const { return mean_diameter_; }
    double soil_density() const { return soil_density_; }
    double soil_kn() const { return soil_kn_; }
    int soil_count() const { return soil_count_; }

    int top_wall() const { return 1; }
    int bottom_wall() const { return 0; }

private:
    ContactLaw soil_law(bool friction_on) const;
    void set_laws(bool friction_on);

    TestScheme scheme_;
    World world_;
    std::unique_ptr<boundary::Membrane> membrane_;
    double solid_volume_ = 0.0, mean_diameter_ = 0.0, soil_density_ = 0.0, soil_kn_ = 0.0;
    double r_mean_ = 0.0;
    int soil_count_ = 0;
    std::vector<double> crush_force_;  // N, per soil grain (Weibull strength x d^2)
    std::vector<double> fatigue_damage_;      // D per soil grain (static fatigue)
    std::vector<double> crush_force_now_;     // N, F_c (1 - D): what the return map uses
    std::vector<double> fatigue_life_scale_;  // (S_i / sigma0)^-2 per soil grain
    bool crushing_on_ = false;
    long crushing_events_ = 0;
};

}  // namespace triax::protocol
