#pragma once
// Stress-controlled lateral boundary without a membrane: the confining pressure acts
// directly on the outermost grains. The lateral surface is cut into cells (n_theta around,
// n_z along the current height); in each cell the grain that reaches farthest out (the
// largest radius rho of its surface within the cell's angles and heights) carries the
// cell's share of the pressure, F = -p rho dtheta dz u, u the cell's outward radial unit
// vector, through the grain's centre (no moment). A flexible membrane does the same: it
// bridges the dips between grains narrower than a cell and touches the grains that stick
// out. Summed over cells the radial force is p times the envelope's lateral area; a grain
// that moves out becomes the outermost in its cells and is pushed back, so none escapes,
// and no lattice adds confinement (the bonded membrane's springs add k eps_r / R,
// docs/diagnosis.md section 6). Cells are the mean grain radius wide.
// Axis = z, specimen centred on it. SI units.
#include <vector>

#include "engine/core/world.hpp"

namespace triax::boundary {

class GrainPressure {
public:
    // Grains are the particles [first, first + count); the cells are cell_size_m wide at
    // the specimen radius.
    GrainPressure(int first, int count, double specimen_radius_m, double height_m, double cell_size_m);

    // Sets the external force of every grain in the range from the pressure (Pa): the
    // outermost grains of each cell get that cell's share, the others none. Returns the
    // total radial force applied (N). Not const: it works in the object's scratch arrays,
    // so one call allocates nothing (it runs every 10 DEM steps of a ~200-grain specimen,
    // where per-call vectors cost a tenth of the run in malloc and heap trimming).
    double apply_pressure(World& world, double pressure_pa, double z_bottom, double z_top);

    // Volume inside the grains' envelope between the platens (m^3): per cell the sector
    // 0.5 rho^2 dtheta dz; a cell no grain reaches takes its row's mean rho.
    double enclosed_volume(const World& world, double z_bottom, double z_top) const;

    // Mean envelope radius over the cells (m).
    double mean_radius(const World& world, double z_bottom, double z_top) const;

    int n_theta() const { return n_theta_; }
    int n_z() const { return n_z_; }

private:
    // Calls visit(grain, cell, rho) for every cell a grain reaches into, with the farthest
    // radius rho (m) its surface reaches within the cell; cells row-major (iz * n_theta + it).
    // Grains whose outermost radius (centre's distance from the axis + radius) is below
    // `inner_m` are not visited (m; a negative value visits all).
    template <class Visit>
    void for_each_reach(const World& world, double z_bottom, double z_top, double inner_m, Visit&& visit) const;
    // Collects reaches_ and rho_ for the grains that reach out to `inner_m` or beyond.
    void collect_reaches(const World& world, double z_bottom, double z_top, double inner_m);
    // Cell index in [0, n_theta) of an unwrapped angular index. A grain's cells lie within
    // about a turn of its centre's angle in [-pi, pi], so one add or subtract does; the
    // integer division (a tenth of the boundary's time) is left for the rounding extremes.
    int wrap(int k) const {
        if (k >= 0 && k < n_theta_) return k;
        if (k < 0 && k >= -n_theta_) return k + n_theta_;
        if (k >= n_theta_ && k < 2 * n_theta_) return k - n_theta_;
        return ((k % n_theta_) + n_theta_) % n_theta_;
    }
    // Per cell the farthest radius any grain reaches (m); 0 where none does.
    std::vector<double> envelope(const World& world, double z_bottom, double z_top) const;

    struct Reach {
        int grain;
        int around;        // angular index of the cell, in [0, n_theta)
        std::size_t cell;  // iz n_theta + around
        double rho;        // m
    };

    int first_ = 0, count_ = 0;
    int n_theta_ = 0, n_z_ = 0;
    double share_depth_ = 0.0;  // m
    // cos and sin of the cell edges (edge k at k dtheta) and of the cell centres, so the
    // reach and the force directions need no trigonometric call per grain and cell.
    std::vector<double> edge_cos_, edge_sin_, centre_cos_, centre_sin_;
    // apply_pressure's scratch: every (grain, cell, reach), per cell the envelope and the
    // sum of the sharing weights.
    std::vector<Reach> reaches_;
    std::vector<double> rho_, weight_sum_;
    // Interior grains: a grain whose outermost radius is below every cell's envelope by more
    // than the sharing depth neither sets an envelope nor shares a force, so apply_pressure
    // skips grains below `inner_m_` (m), set from the previous call's lowest envelope with
    // room for the grains' motion between calls, and checks the premise on the new envelope
    // (else it visits every grain): the forces are the bits of a visit of every grain.
    double inner_m_ = -1.0;
};

}  // namespace triax::boundary
