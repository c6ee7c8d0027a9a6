#pragma once
// The triaxial specimen as a DEM model: soil spheres inside the bonded-particle membrane
// between two rigid platens (plane walls), and the measurements on it. Axis z, centre at
// the origin; groups: soil 0, membrane 1, platens 2. SI units, compression positive.
#include <functional>
#include <memory>
#include <random>

#include "engine/boundary/grain_pressure.hpp"
#include "engine/boundary/membrane.hpp"
#include "engine/contact/grain_crushing.hpp"
#include "engine/core/world.hpp"
#include "engine/protocol/test_scheme.hpp"

namespace triax::protocol {

constexpr int kSoilGroup = 0;
constexpr int kMembraneGroup = 1;
constexpr int kPlatenGroup = 2;

// Thrown by the specimen's generation and by cycle() when the caller's cancel check
// (set_cancel_check) answers true: the run stops within one chunk of cycles.
struct SpecimenCancelled {};

class Specimen {
public:
    // Generates the soil at the target porosity by radius expansion inside the (held)
    // membrane: radii drawn from the gradation fill (1 - n) of the specimen volume, are
    // placed at 60 % size without overlap (seeded), then grown to full size in steps with
    // frictionless contacts, and relaxed to equilibrium. Deterministic for scheme.seed.
    // With scheme.packing the grains are the imported ones instead (validated against the
    // specimen, validate_packing): no generation, the platens and membrane are put back
    // as the packing had them or built around its grains (imported_packing.hpp), and the
    // protocol runs from there. `cancelled` (optional) is polled while
    // grains are placed and grown and becomes the cancel check of cycle() (SpecimenCancelled).
    explicit Specimen(const TestScheme& scheme, std::function<bool()> cancelled = {});
    // A deep copy (world and membrane): a second test on the same consolidated specimen
    // without generating and consolidating it again.
    Specimen(const Specimen& other);
    Specimen& operator=(const Specimen&) = delete;

    World& world() { return world_; }
    const World& world() const { return world_; }
    // The bonded membrane; null with the grain-pressure lateral boundary.
    boundary::Membrane* membrane() { return membrane_.get(); }
    int membrane_particle_count() const { return membrane_ ? membrane_->count() : 0; }
    // Frees the lateral boundary held during generation (start of consolidation): the
    // membrane's spheres are released, or the generation's rigid cylinder is moved clear
    // and the pressure goes onto the outermost grains.
    void release_lateral_boundary();

    // Switches to the test's contact laws (friction on; bond strength per moisture).
    void install_test_laws();
    // The test laws with the soil's friction times specimen.compaction_friction_ratio
    // (consolidation); install_test_laws() restores the shear's.
    void install_compaction_laws();
    // Makes the grain contacts crushable (if micro.crushing_strength_pa > 0), on the
    // consolidated fabric: the overlaps the radius expansion locks in are a packing
    // device, not loads, and would crush into a denser specimen (docs/protocol.md).
    void enable_crushing();
    // Installs soil-soil contact bonds on the current contacts (strength per contact
    // = strength (Pa) x pi r_min^2 of the pair, scaled by the moisture relation).
    long install_soil_bonds();

    // Cycles n steps, refreshing the confining forces (membrane followers, or the outermost
    // grains') every few steps; crushable
    // contacts are return-mapped after every such chunk.
    // Throws SpecimenCancelled when the cancel check answers true (polled once a call).
    void cycle(long n, double confining_pa);
    void set_cancel_check(std::function<bool()> cancelled) { cancelled_ = std::move(cancelled); }
    // Crushing events (contacts x passes) since enable_crushing().
    long crushing_events() const { return crushing_events_; }
    // Grain i's crushing force F_c (N); empty when crushing is off.
    const std::vector<double>& crushing_forces() const { return crush_force_; }

    // Displacement and rotation reference: the positions now, rotations zeroed (the start
    // of consolidation). Rotations accumulate over cycle() (omega dt at each membrane update).
    void mark_reference();
    const std::vector<Vec3>& reference_positions() const { return reference_; }
    const std::vector<Vec3>& rotation() const { return rotation_; }
    bool crushing_on() const { return crushing_on_; }

    double top_z() const;
    double bottom_z() const;
    double height() const { return top_z() - bottom_z(); }
    double volume() const;                       // inside the membrane or the grains' envelope, m^3
    double axial_stress() const;                 // mean of both platens, Pa
    double top_stress() const;
    double solid_volume() const { return solid_volume_; }
    double porosity() const { return 1.0 - solid_volume_ / volume(); }
    double mean_diameter() const { return mean_diameter_; }
    // The grain radii the contact stiffness (mean), the time step and the automatic membrane
    // (smallest) were sized from: the drawn radii, before the growth's rounding (m).
    double sizing_mean_radius() const { return r_mean_; }
    double sizing_min_radius() const { return r_min_; }
    double soil_density() const { return soil_density_; }
    double soil_kn() const { return soil_kn_; }
    int soil_count() const { return soil_count_; }

    int top_wall() const { return 1; }
    int bottom_wall() const { return 0; }

private:
    ContactLaw soil_law(bool friction_on, double friction_ratio = 1.0) const;
    void set_laws(bool friction_on, double friction_ratio = 1.0);

    TestScheme scheme_;
    World world_;
    std::unique_ptr<boundary::Membrane> membrane_;            // BondedMembrane
    std::unique_ptr<boundary::GrainPressure> grain_pressure_;  // GrainPressure
    double solid_volume_ = 0.0, mean_diameter_ = 0.0, soil_density_ = 0.0, soil_kn_ = 0.0;
    double r_mean_ = 0.0;
    double r_min_ = 0.0;  // smallest grain radius the membrane and the time step were sized from
    int soil_count_ = 0;
    std::vector<double> crush_force_;  // N, per soil grain (Weibull strength x d^2)
    bool crushing_on_ = false;
    long crushing_events_ = 0;
    std::function<bool()> cancelled_;
    void poll_cancel() const {
        if (cancelled_ && cancelled_()) throw SpecimenCancelled{};
    }
    std::vector<Vec3> reference_;  // m, positions at mark_reference() (all particles)
    std::vector<Vec3> rotation_;   // rad, accumulated rotation vector since then
};

}  // namespace triax::protocol
