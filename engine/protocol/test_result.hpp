#pragma once
// TestResult: everything one run of the protocol reports. SI units with the unit in every
// field name; soil-mechanics signs (compression positive for stresses and strains,
// volumetric strain positive = contraction). Lab units are applied at the edge
// (server/io/result_json, result_csv).
#include <string>
#include <vector>

namespace triax::protocol {

struct ShearPoint {
    double axial_strain = 0.0;          // -, compression positive
    double q_pa = 0.0;                  // sigma1 - sigma3
    double p_pa = 0.0;                  // (sigma1 + 2 sigma3) / 3
    double sigma1_pa = 0.0;
    double sigma3_pa = 0.0;
    double volumetric_strain = 0.0;     // -, contraction positive (membrane-enclosed volume)
    double inertial_number = 0.0;
};

struct CreepPoint {
    double time_s = 0.0;                 // physical time since the start of the stage (or test)
    double axial_deformation_m = 0.0;    // shortening, positive
    double axial_strain = 0.0;
};

struct CreepStageResult {
    int stage = 0;                       // 1-based
    double stress_level = 0.0;           // q / q_f
    double stress_level_eq1 = 0.0;       // paper Eq. 1
    double q_pa = 0.0;                   // held deviator
    double duration_s = 0.0;
    double start_time_s = 0.0;           // physical time of the stage start in the whole creep test
    std::vector<CreepPoint> raw;         // time since creep start, cumulative deformation
    std::vector<CreepPoint> translated;  // coordinate-translated: time and deformation from the stage start (Boltzmann)
    double instant_deformation_m = 0.0;  // transient elastic part (at loading)
    double final_deformation_m = 0.0;    // total stage deformation at the end
    double share_in_first_30min = 0.0;   // fraction of the stage's creep (final - instant) reached at 30 min
    // Fraction of the stage's whole deformation (instant + creep) reached at 30 min: the
    // paper's own measure ("transient elastic and rapid deformation ... 75 % ~ 85 % of the
    // total deformation"), which counts the loading step.
    double total_share_in_first_30min = 0.0;
    double elastic_share = 0.0;          // instant / final
    bool converged = false;              // creep rate decays (not accelerating) at the end
    bool accelerating = false;           // tertiary creep detected late in the stage
    // Creep rupture: the platen ran away or the specimen collapsed (creep_regime.hpp); the
    // stage, and the test, end at rupture_time_s (stage time), as a lab's would.
    bool ruptured = false;
    double rupture_time_s = 0.0;
};

// The reading on a stage's translated curve at stage time t_s: the last one at or before
// t_s (readings are what the lab has; no interpolation between them).
inline const CreepPoint& reading_at(const CreepStageResult& st, double t_s) {
    const CreepPoint* r = &st.translated.front();
    for (const auto& p : st.translated)
        if (p.time_s <= t_s) r = &p;
    return *r;
}

// Deformation (m) of that reading.
inline double deformation_at(const CreepStageResult& st, double t_s) { return reading_at(st, t_s).axial_deformation_m; }

// One sample of the energy ledger (cumulative, J).
struct EnergySample {
    int phase_index = 0;                 // 0 consolidation, 1 shear, 2.. creep stages
    long step = 0;
    double time_s = 0.0;                 // physical time (creep); 0 before creep
    double strain_j = 0.0;               // stored in contact springs (current)
    double slip_j = 0.0;                 // frictional dissipation (cumulative)
    double damping_j = 0.0;              // local damping (cumulative)
    double kinetic_j = 0.0;              // current
    double bond_j = 0.0;                 // stored in bond springs (current)
    double boundary_work_j = 0.0;        // done by platens and membrane pressure (cumulative)
    double creep_j = 0.0;                // dissipated by viscous slip (cumulative)
    double breakage_j = 0.0;             // dissipated by crushing contacts (cumulative)
};

struct MeasurementSample {
    int sphere = 0;                      // 1: z=+80 mm (scaled with height), 2: 0, 3: -80 mm
    long step = 0;
    double time_s = 0.0;
    double z_displacement_m = 0.0;       // mean z displacement of particles inside since creep start
    double rotation_rate_x_rad_s = 0.0;
    double rotation_rate_y_rad_s = 0.0;
    double rotation_rate_z_rad_s = 0.0;
    double porosity = 0.0;
    double coordination = 0.0;
};

struct ConsolidationSummary {
    double unbalanced_force_ratio = 0.0; // mean unbalanced force / mean contact force at the end
    double porosity = 0.0;
    long steps = 0;
    double achieved_sigma3_pa = 0.0;     // measured on the platens
};

struct TestResult {
    std::string scheme_name;
    int particle_count = 0;              // soil particles
    int membrane_particle_count = 0;
    double initial_porosity = 0.0;
    double sigma3_pa = 0.0;
    ConsolidationSummary consolidation;
    std::vector<ShearPoint> shear;
    double q_failure_pa = 0.0;
    double axial_strain_at_failure = 0.0;
    double max_inertial_number = 0.0;    // with the density-scaled grain density below
    double inertial_density_kg_m3 = 0.0; // grain density with density scaling (mass-weighted), shear
    std::vector<CreepStageResult> creep_stages;
    std::vector<EnergySample> energies;
    std::vector<MeasurementSample> measurements;
    double measurement_sphere_radius_m = 0.0;
    bool converged = true;               // all required stages ended normally
    bool cancelled = false;
    double wall_time_s = 0.0;
    long total_steps = 0;
    long creep_relaxations = 0;          // mechanical relaxations of the creep stages (sub-increments)
};

}  // namespace triax::protocol
