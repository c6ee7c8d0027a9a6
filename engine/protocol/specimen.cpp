#include "engine/protocol/specimen.hpp"

#include <algorithm>
#include <cmath>

#include "engine/creep/moisture_bond.hpp"
#include "engine/protocol/gradation.hpp"
#include "engine/protocol/imported_packing.hpp"

namespace triax::protocol {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr int kMembraneUpdateEvery = 10;

GrainCrushingParams crushing_params(const TestScheme& s) {
    GrainCrushingParams p;
    p.strength_pa = s.micro.crushing_strength_pa;
    p.reference_diameter_m = s.micro.crushing_reference_diameter_m;
    p.weibull_modulus = s.micro.crushing_weibull_modulus;
    return p;
}
}  // namespace

Specimen::Specimen(const TestScheme& s, std::function<bool()> cancelled) : scheme_(s), cancelled_(std::move(cancelled)) {
    s.validate();
    const double R = 0.5 * s.specimen.diameter_m, H = s.specimen.height_m;
    const double v_total = kPi * R * R * H;
    solid_volume_ = (1.0 - s.specimen.target_porosity) * v_total;
    // Grain density from the dry density at the target porosity: rho_d = rho_s (1 - n).
    soil_density_ = s.specimen.dry_density_kg_m3 / (1.0 - s.specimen.target_porosity);

    const bool imported = s.packing != nullptr;
    if (imported) validate_packing(*s.packing, s);
    std::mt19937_64 rng(s.seed);
    GradationSpec g = s.gradation;
    std::vector<double> radii = imported ? s.packing->radius : draw_radii(g, solid_volume_, rng);
    if (imported) {
        solid_volume_ = 0.0;
        for (double r : radii) solid_volume_ += 4.0 / 3.0 * kPi * r * r * r;
    }
    if (!imported && s.max_particles > 0 && static_cast<int>(radii.size()) > s.max_particles) {
        // Reduced specimen: the same gradation shape scaled up until the count fits.
        const double f = std::cbrt(static_cast<double>(radii.size()) / s.max_particles) * 1.02;
        g.r_min_m *= f;
        for (auto& p : g.sieve_curve) p.size_m *= f;
        g.fines_cutoff_m *= f;
        rng.seed(s.seed);
        radii = draw_radii(g, solid_volume_, rng);
    }
    soil_count_ = static_cast<int>(radii.size());
    if (s.micro.crushing_strength_pa > 0.0) {
        // Each grain's Weibull survival quantile, from its own stream (the placement
        // below draws the same numbers with crushing on or off).
        const GrainCrushingParams cp = crushing_params(s);
        std::mt19937_64 strength_rng(s.seed ^ 0x9E3779B97F4A7C15ull);
        std::uniform_real_distribution<double> uq(0.0, 1.0);
        crush_force_.resize(radii.size());
        for (std::size_t q = 0; q < radii.size(); ++q) {
            const double u = std::clamp(uq(strength_rng), 1e-12, 1.0 - 1e-12);
            crush_force_[q] = grain_crushing_force(cp, 2.0 * radii[q], u);
        }
    }
    double rsum = 0.0, rmin = 1e9;
    for (double r : radii) { rsum += r; rmin = std::min(rmin, r); }
    r_mean_ = rsum / soil_count_;
    // An exported state names the radii its stiffness, time step and membrane were sized
    // from (the drawn radii; grown grains differ from them in the last bits).
    if (imported && s.packing->mean_radius_m > 0.0) r_mean_ = s.packing->mean_radius_m;
    if (imported && s.packing->min_radius_m > 0.0) rmin = s.packing->min_radius_m;
    r_min_ = rmin;
    mean_diameter_ = 2.0 * r_mean_;
    // Table 3 moduli (docs/parameters.md): kn = pi r_mean E_n / 2 for the mean grain.
    soil_kn_ = 0.5 * kPi * r_mean_ * s.micro.normal_modulus_pa;

    // Soil placed at 60 % of final size, largest first, rejection sampling (an imported
    // packing is placed as it is, at full size).
    const double shrink = imported ? 1.0 : 0.6;
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Vec3> placed;
    placed.reserve(radii.size());
    for (std::size_t q = 0; q < radii.size() && imported; ++q) placed.push_back(s.packing->position[q]);
    for (double r_full : radii) {
        if (imported) break;
        poll_cancel();  // placement is O(N^2): a grain can take milliseconds when N is large
        const double r = shrink * r_full;
        Vec3 best = Vec3::Zero();
        double best_gap = -1e9;
        for (int attempt = 0; attempt < 300; ++attempt) {
            const double rr = (R - r_full) * std::sqrt(u(rng)), th = 2.0 * kPi * u(rng);
            const Vec3 x(rr * std::cos(th), rr * std::sin(th), -0.5 * H + r_full + (H - 2.0 * r_full) * u(rng));
            double gap = 1e9;
            for (std::size_t q = 0; q < placed.size(); ++q)
                gap = std::min(gap, (x - placed[q]).norm() - r - shrink * radii[q]);
            if (gap > best_gap) { best_gap = gap; best = x; }
            if (gap >= 0.0) break;
        }
        placed.push_back(best);
    }
    for (std::size_t q = 0; q < radii.size(); ++q) world_.add_sphere(placed[q], shrink * radii[q], soil_density_, kSoilGroup);

    const bool membrane = s.specimen.lateral_boundary == SpecimenSpec::LateralBoundary::BondedMembrane;
    // The boundary: the scheme's cylinder, or the one an imported packing makes (its own
    // height and girth: a consolidated specimen has shrunk, a sheared one has bulged).
    const PackingExtent e = imported ? packing_extent(*s.packing) : PackingExtent{R, -0.5 * H, 0.5 * H};
    bool restore_membrane = false;
    if (membrane) {
        double rm = s.micro.membrane_particle_radius_m;
        if (rm <= 0.0) rm = boundary::automatic_membrane_radius(rmin, r_mean_, s.specimen.diameter_m);
        // An exported membrane of the scheme's lattice (built at D/2 and H around the
        // origin, the generation's) is bonded as built, then moved to where it was.
        if (imported) {
            const auto& mr = s.packing->membrane_radius;
            restore_membrane = !mr.empty() && static_cast<int>(mr.size()) == boundary::Membrane::lattice_count(R, H, rm) &&
                               std::all_of(mr.begin(), mr.end(), [&](double r) { return std::abs(r - rm) <= 1e-9 * rm; });
        }
        const PackingExtent lattice = restore_membrane ? PackingExtent{R, -0.5 * H, 0.5 * H} : e;
        membrane_ = std::make_unique<boundary::Membrane>(world_, lattice.radius_m, lattice.height_m(), rm, 1000.0,
                                                         kMembraneGroup, lattice.centre_z_m());
    } else {
        grain_pressure_ = std::make_unique<boundary::GrainPressure>(0, soil_count_, e.radius_m, e.height_m(), r_mean_);
        // Generation's container: a rigid cylinder with the grain-membrane law (frictionless).
        world_.add_cylinder_wall(Vec3(0, 0, e.bottom_z_m), Vec3::UnitZ(), e.radius_m, e.height_m(), kMembraneGroup);
    }
    world_.add_plane_wall(Vec3(0, 0, e.bottom_z_m), Vec3::UnitZ(), kPlatenGroup);
    world_.add_plane_wall(Vec3(0, 0, e.top_z_m), -Vec3::UnitZ(), kPlatenGroup);
    world_.set_domain(Vec3(-3 * R, -3 * R, -1.5 * H), Vec3(3 * R, 3 * R, 1.5 * H));
    set_laws(false);
    world_.set_local_damping(s.micro.local_damping);
    world_.set_density_scaling(true);
    world_.set_threads(s.threads);
    // Density scaling makes any dt stable (grains lighter than 4 k dt^2 are given that
    // inertia); the step of the smallest grain, but no smaller than a fifth of the mean
    // grain's, keeps wide gradations affordable. Only equilibrium states are used.
    const double r_dt = std::max(rmin, 0.2 * r_mean_);
    const double m_dt = soil_density_ * 4.0 / 3.0 * kPi * r_dt * r_dt * r_dt;
    world_.set_time_step(0.5 * std::sqrt(m_dt / soil_kn_));
    if (membrane_) {
        membrane_->bond(world_, 1.0e9);
        membrane_->set_fixed(world_, true);
        if (restore_membrane) membrane_->restore(world_, s.packing->membrane_position);
    }

    auto& p = world_.particles();
    if (imported) {
        // An exported equilibrium state carries its residual velocities (an exact restart).
        for (std::size_t q = 0; q < s.packing->velocity.size() && q < radii.size(); ++q) p.velocity[q] = s.packing->velocity[q];
        for (std::size_t q = 0; q < s.packing->angular_velocity.size() && q < radii.size(); ++q)
            p.angular_velocity[q] = s.packing->angular_velocity[q];
        if (s.packing->mass.size() == radii.size() && s.packing->inertia.size() == radii.size())
            for (std::size_t q = 0; q < radii.size(); ++q) {
                p.mass[q] = s.packing->mass[q];
                p.inertia[q] = s.packing->inertia[q];
            }
        for (std::size_t k = 0; k < s.packing->platen_force_n.size() && k < 2; ++k) {
            auto& wall = world_.plane_wall(static_cast<int>(k));
            wall.force = -s.packing->platen_force_n[k] * wall.normal;
        }
        return;
    }
    // Radius expansion to full size, frictionless, inside the held membrane.
    constexpr int kGrowthSteps = 16;
    for (int k = 1; k <= kGrowthSteps; ++k) {
        const double f = (shrink + (1.0 - shrink) * k / kGrowthSteps) / (shrink + (1.0 - shrink) * (k - 1) / kGrowthSteps);
        for (int q = 0; q < soil_count_; ++q) {
            p.radius[q] *= f;
            p.mass[q] *= f * f * f;
            p.inertia[q] *= f * f * f * f * f;
        }
        world_.invalidate_neighbors();
        poll_cancel();
        world_.cycle(300);
    }
    for (int k = 0; k < 40 && world_.unbalanced_force_ratio() > 0.01; ++k) {
        poll_cancel();
        world_.cycle(250);
    }
}

Specimen::Specimen(const Specimen& o)
    : scheme_(o.scheme_),
      world_(o.world_),
      membrane_(o.membrane_ ? std::make_unique<boundary::Membrane>(*o.membrane_) : nullptr),
      grain_pressure_(o.grain_pressure_ ? std::make_unique<boundary::GrainPressure>(*o.grain_pressure_) : nullptr),
      solid_volume_(o.solid_volume_),
      mean_diameter_(o.mean_diameter_),
      soil_density_(o.soil_density_),
      soil_kn_(o.soil_kn_),
      r_mean_(o.r_mean_),
      r_min_(o.r_min_),
      soil_count_(o.soil_count_),
      crush_force_(o.crush_force_),
      crushing_on_(o.crushing_on_),
      crushing_events_(o.crushing_events_),
      cancelled_(o.cancelled_),
      reference_(o.reference_),
      rotation_(o.rotation_) {}

ContactLaw Specimen::soil_law(bool friction_on, double friction_ratio) const {
    ContactLaw l;
    l.kn = soil_kn_;
    l.ks = soil_kn_ * scheme_.micro.shear_modulus_pa / scheme_.micro.normal_modulus_pa;
    l.friction = friction_on ? friction_ratio * scheme_.micro.friction : 0.0;
    l.bond_friction = scheme_.micro.bond_friction;
    l.bond_rolling_friction = friction_on ? scheme_.micro.bond_rolling_friction : 0.0;
    l.rolling_friction = friction_on ? scheme_.micro.rolling_friction : 0.0;
    return l;
}

void Specimen::set_laws(bool friction_on, double friction_ratio) {
    world_.set_contact_law(kSoilGroup, kSoilGroup, soil_law(friction_on, friction_ratio));
    ContactLaw sm;  // soil on membrane, frictionless. The membrane's flexibility is in its
    // bonds; the grain-membrane contact is as stiff as a grain contact so that grains
    // cannot be pushed through the membrane layer (a soft contact let small grains escape).
    sm.kn = soil_kn_;
    sm.ks = 0.0;
    sm.friction = 0.0;
    world_.set_contact_law(kSoilGroup, kMembraneGroup, sm);
    ContactLaw mm;
    mm.kn = mm.ks = scheme_.micro.membrane_stiffness_n_m;
    mm.friction = 0.0;
    world_.set_contact_law(kMembraneGroup, kMembraneGroup, mm);
    ContactLaw ws;
    // Table 3 platens (1e8 N/m) are far stiffer than a grain contact; above ~10 x the
    // grain stiffness the platen is rigid for the skeleton, while a stiffer spring only
    // slows density-scaled relaxation (docs/parameters.md).
    ws.kn = std::min(scheme_.micro.wall_normal_stiffness_n_m, 10.0 * soil_kn_);
    ws.ks = std::min(scheme_.micro.wall_shear_stiffness_n_m, 10.0 * soil_kn_);
    ws.friction = friction_on ? scheme_.micro.wall_friction : 0.0;
    world_.set_contact_law(kSoilGroup, kPlatenGroup, ws);
    ContactLaw wm;
    wm.kn = scheme_.micro.membrane_stiffness_n_m;
    wm.ks = 0.0;
    wm.friction = 0.0;
    world_.set_contact_law(kMembraneGroup, kPlatenGroup, wm);
}

void Specimen::install_test_laws() { set_laws(true); }

void Specimen::install_compaction_laws() { set_laws(true, scheme_.specimen.compaction_friction_ratio); }

void Specimen::enable_crushing() { crushing_on_ = !crush_force_.empty(); }

long Specimen::install_soil_bonds() {
    // No cement, no bond: a zero-strength bond would still act as a Mohr-Coulomb contact
    // with the bond's friction instead of the grains'.
    const auto& m = scheme_.micro;
    if (m.bond_normal_strength_pa <= 0.0 && m.bond_shear_strength_pa <= 0.0) return 0;
    const double factor = scheme_.effects.moisture_bonding ? creep::bond_strength_factor(scheme_.specimen.moisture_content) : 1.0;
    world_.bond_contacts(kSoilGroup, kSoilGroup, 1.0e-3 * r_mean_, 1.0, 1.0);
    auto& c = world_.contacts();
    const auto& r = world_.particles().radius;
    long n = 0;
    for (std::size_t k = 0; k < c.i.size(); ++k) {
        if (!c.bonded[k]) continue;
        const int a = c.i[k], b = c.j[k];
        if (world_.particles().group[a] != kSoilGroup || world_.particles().group[b] != kSoilGroup) continue;
        const double rmin = std::min(r[a], r[b]);
        const double cross_section = kPi * rmin * rmin;
        c.bond_normal_strength[k] = factor * (scheme_.micro.bond_normal_strength_pa * cross_section);
        c.bond_shear_strength[k] = factor * (scheme_.micro.bond_shear_strength_pa * cross_section);
        ++n;
    }
    return n;
}

void Specimen::cycle(long n, double confining_pa) {
    poll_cancel();
    for (long done = 0; done < n; done += kMembraneUpdateEvery) {
        if (membrane_)
            membrane_->apply_pressure(world_, confining_pa);
        else
            grain_pressure_->apply_pressure(world_, confining_pa, bottom_z(), top_z());
        const long m = std::min<long>(kMembraneUpdateEvery, n - done);
        world_.cycle(m);
        const auto& omega = world_.particles().angular_velocity;
        for (std::size_t i = 0; i < rotation_.size(); ++i) rotation_[i] += omega[i] * (m * world_.time_step());
        if (crushing_on_) {
            const CrushSummary c = crush_contacts(world_.contacts(), world_.particles(), soil_count_, crush_force_,
                                                  soil_kn_, scheme_.micro.crushing_hardening_ratio,
                                                  scheme_.micro.crushing_breaks_bond);
            crushing_events_ += c.crushing;
            world_.energy().breakage += c.dissipated_j;
        }
    }
}

void Specimen::mark_reference() {
    reference_ = world_.particles().position;
    rotation_.assign(reference_.size(), Vec3::Zero());
}

double Specimen::top_z() const { return world_.plane_wall_count() ? const_cast<World&>(world_).plane_wall(1).point.z() : 0.0; }
double Specimen::bottom_z() const { return const_cast<World&>(world_).plane_wall(0).point.z(); }

double Specimen::volume() const {
    return membrane_ ? membrane_->enclosed_volume(world_, bottom_z(), top_z())
                     : grain_pressure_->enclosed_volume(world_, bottom_z(), top_z());
}

void Specimen::release_lateral_boundary() {
    if (membrane_) {
        membrane_->set_fixed(world_, false);
        return;
    }
    // The cylinder cannot be removed from the world: it is moved to the domain's edge,
    // beyond any bulge of the test (the domain is 6 radii wide).
    auto& cylinder = world_.cylinder_wall(0);
    cylinder.radius = 2.9 * 0.5 * scheme_.specimen.diameter_m;
    world_.invalidate_neighbors();
}

double Specimen::top_stress() const {
    const double area = volume() / height();
    return const_cast<World&>(world_).plane_wall(1).normal_stress(area);
}

double Specimen::axial_stress() const {
    const double area = volume() / height();
    auto& w = const_cast<World&>(world_);
    return 0.5 * (w.plane_wall(0).normal_stress(area) + w.plane_wall(1).normal_stress(area));
}

}  // namespace triax::protocol
