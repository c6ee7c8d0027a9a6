// Cross-engine check, triax side (bench/cross_engine/README.md; never run by CI). One
// packing of N spheres in a rigid box of six frictionless walls, the same test that
// bench/cross_engine/yade_box.py runs in YADE:
//   1. packing: spheres of 1.0-1.5 mm placed at 60 % size in a 30 mm box, grown to full size
//      frictionless (engine_bench's radius expansion) and relaxed; exported as a sphere list
//      (packing.txt, SI) with the box (params.json) for YADE;
//   2. isotropic compression to 100 kPa, friction 0.4, every wall on the same servo;
//   3. drained shear to 10 % axial strain: top and bottom walls at +-rate L/2, the four
//      lateral walls on the servo at 100 kPa.
// Linear law kn = pi r_mean E_n / 2, ks = pi r_mean E_s / 2 (Table 3 moduli), Coulomb 0.4,
// no bonds, no viscous damping, local damping 0.7, true masses (no density scaling), one dt.
// Writes triax_curve.csv (axial_strain_pct, q_kPa, volumetric_strain_pct, p_kPa).
//
// Usage: cross_engine_box OUT_DIR [N=2000] [ISO_STEPS=60000] [RATE_PER_S=2]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "engine/core/world.hpp"
#include "engine/protocol/specimen_snapshot.hpp"
#include "server/io/packing_formats.hpp"

using namespace triax;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDensity = 2650.0;
constexpr double kRmin = 1.0e-3, kRmax = 1.5e-3;
constexpr double kEn = 230.15e6, kEs = 150.63e6;  // Table 3 moduli (docs/parameters.md)
constexpr double kFriction = 0.4, kDamping = 0.7;
constexpr double kSigma3 = 100e3;
double kRate = 2.0;                                // axial strain rate, 1/s (2: inertial number ~4e-4)
constexpr long kServoEvery = 10;                   // steps between servo updates (both engines)
// Servo gain (m/s per unit relative stress error) and speed cap (m/s): 0.3 and 0.05 for the
// isotropic compression; in the shear in proportion to the loading rate (the same at 2 /s)
// so that the lateral walls can follow the specimen's expansion.
double kServoGain = 0.3;
double kServoVmax = 0.05;
long kIsoSteps = 60000;
constexpr long kSampleEvery = 1000;

struct Rng {
    std::uint64_t s;
    explicit Rng(std::uint64_t seed) : s(seed * 2654435761ULL + 1) {}
    double uniform() {
        s ^= s << 13; s ^= s >> 7; s ^= s << 17;
        return static_cast<double>(s >> 11) * (1.0 / 9007199254740992.0);
    }
};

// Walls 0..5: -x, +x, -y, +y, -z, +z.
Vec3 lengths(World& w) {
    return Vec3(w.plane_wall(1).point.x() - w.plane_wall(0).point.x(), w.plane_wall(3).point.y() - w.plane_wall(2).point.y(),
                w.plane_wall(5).point.z() - w.plane_wall(4).point.z());
}
Vec3 wall_stress(World& w) {
    const Vec3 l = lengths(w);
    const double ax[3] = {l.y() * l.z(), l.x() * l.z(), l.x() * l.y()};
    Vec3 s;
    for (int a = 0; a < 3; ++a)
        s[a] = 0.5 * (w.plane_wall(2 * a).normal_stress(ax[a]) + w.plane_wall(2 * a + 1).normal_stress(ax[a]));
    return s;
}
// Servo on the walls of the axes marked: each wall of an axis at v = gain (s - target)/target
// outward when over-stressed (clamped).
void servo(World& w, bool axes[3]) {
    const Vec3 s = wall_stress(w);
    for (int a = 0; a < 3; ++a) {
        if (!axes[a]) continue;
        const double v = std::clamp(kServoGain * (s[a] - kSigma3) / kSigma3, -kServoVmax, kServoVmax);
        Vec3 d = Vec3::Zero();
        d[a] = v;
        w.plane_wall(2 * a).velocity = -d;
        w.plane_wall(2 * a + 1).velocity = d;
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: cross_engine_box OUT_DIR [N=2000] [ISO_STEPS=60000] [RATE_PER_S=2]\n");
        return 2;
    }
    const std::filesystem::path out = argv[1];
    const int n = argc > 2 ? std::atoi(argv[2]) : 2000;
    if (argc > 3) kIsoSteps = std::atol(argv[3]);
    if (argc > 4) kRate = std::atof(argv[4]);
    std::filesystem::create_directories(out);
    const double r_mean = 0.5 * (kRmin + kRmax);
    const double kn = 0.5 * kPi * r_mean * kEn, ks = 0.5 * kPi * r_mean * kEs;
    // Box for a solid fraction of 0.45 at full size.
    double v_solid = 0.0;
    Rng rng(7);
    std::vector<double> radii(n);
    for (auto& r : radii) {
        r = kRmin + (kRmax - kRmin) * rng.uniform();
        v_solid += 4.0 / 3.0 * kPi * r * r * r;
    }
    const double L = std::cbrt(v_solid / 0.45);
    World w;
    ContactLaw law;
    law.kn = kn;
    law.ks = ks;
    law.friction = 0.0;
    w.set_contact_law(0, 0, law);
    ContactLaw wall = law;
    wall.friction = 0.0;
    w.set_contact_law(0, 1, wall);
    w.add_plane_wall(Vec3(0, 0, 0), Vec3::UnitX(), 1);
    w.add_plane_wall(Vec3(L, 0, 0), -Vec3::UnitX(), 1);
    w.add_plane_wall(Vec3(0, 0, 0), Vec3::UnitY(), 1);
    w.add_plane_wall(Vec3(0, L, 0), -Vec3::UnitY(), 1);
    w.add_plane_wall(Vec3(0, 0, 0), Vec3::UnitZ(), 1);
    w.add_plane_wall(Vec3(0, 0, L), -Vec3::UnitZ(), 1);
    // Placed at 60 % size without overlap (rejection), then grown in 20 steps.
    std::vector<Vec3> placed;
    for (double r_full : radii) {
        const double r = 0.6 * r_full;
        Vec3 x;
        for (int attempt = 0; attempt < 2000; ++attempt) {
            x = Vec3(r_full + (L - 2 * r_full) * rng.uniform(), r_full + (L - 2 * r_full) * rng.uniform(),
                     r_full + (L - 2 * r_full) * rng.uniform());
            bool free = true;
            for (std::size_t q = 0; q < placed.size() && free; ++q) free = (x - placed[q]).norm() >= r + 0.6 * radii[q];
            if (free) break;
        }
        placed.push_back(x);
        w.add_sphere(x, r, kDensity);
    }
    const double m_min = kDensity * 4.0 / 3.0 * kPi * std::pow(kRmin, 3);
    const double dt = 0.2 * std::sqrt(m_min / kn);
    w.set_time_step(dt);
    w.set_local_damping(kDamping);
    w.set_skin(0.1 * kRmin);
    auto& p = w.particles();
    for (int k = 1; k <= 20; ++k) {
        for (int q = 0; q < n; ++q) {
            const double r = radii[q] * (0.6 + 0.4 * k / 20.0);
            p.radius[q] = r;
            p.mass[q] = kDensity * 4.0 / 3.0 * kPi * r * r * r;
            p.inertia[q] = 0.4 * p.mass[q] * r * r;
        }
        w.invalidate_neighbors();
        w.cycle(500);
    }
    for (int k = 0; k < 40 && w.unbalanced_force_ratio() > 0.01; ++k) w.cycle(500);
    for (auto& v : p.velocity) v.setZero();
    for (auto& v : p.angular_velocity) v.setZero();
    {
        const auto snap = protocol::snapshot_of_world(w, "box", {}, {}, {});
        std::ofstream(out / "packing.txt") << io::snapshot_sphere_list(snap);
        std::ofstream f(out / "params.json");
        char b[1024];
        std::snprintf(b, sizeof b,
                      "{\"box_m\": [%.17g, %.17g, %.17g], \"kn_N_m\": %.17g, \"ks_N_m\": %.17g, \"friction\": %g, "
                      "\"density_kg_m3\": %g, \"local_damping\": %g, \"dt_s\": %.17g, \"sigma3_Pa\": %g, "
                      "\"strain_rate_per_s\": %g, \"servo_every\": %ld, \"servo_gain_m_s\": %g, \"servo_vmax_m_s\": %g, "
                      "\"shear_servo_gain_m_s\": %g, \"shear_servo_vmax_m_s\": %g, "
                      "\"iso_steps\": %ld, \"sample_every\": %ld, \"max_axial_strain\": 0.1}\n",
                      L, L, L, kn, ks, kFriction, kDensity, kDamping, dt, kSigma3, kRate, kServoEvery, kServoGain,
                      kServoVmax, 0.15 * kRate, 0.025 * kRate, kIsoSteps, kSampleEvery);
        f << b;
    }
    std::fprintf(stderr, "packing: %d spheres, box %.3f mm, dt %.3g s, kn %.4g N/m, ks %.4g N/m\n", n, 1e3 * L, dt, kn, ks);

    // From here the two engines run the same script on the same packing.
    law.friction = kFriction;
    w.set_contact_law(0, 0, law);
    bool all[3] = {true, true, true}, lateral[3] = {true, true, false};
    for (long s = 0; s < kIsoSteps; s += kServoEvery) {
        servo(w, all);
        w.cycle(kServoEvery);
    }
    const Vec3 s_iso = wall_stress(w);
    std::fprintf(stderr, "isotropic: stress %.2f %.2f %.2f kPa, solid fraction %.4f\n", 1e-3 * s_iso.x(), 1e-3 * s_iso.y(),
                 1e-3 * s_iso.z(), v_solid / lengths(w).prod());
    const Vec3 l0 = lengths(w);
    const double v0 = l0.prod();
    std::ofstream csv(out / "triax_curve.csv");
    csv << "axial_strain_pct,q_kPa,volumetric_strain_pct,p_kPa\n";
    const double vz = 0.5 * kRate * l0.z();
    kServoGain = 0.15 * kRate;
    kServoVmax = 0.025 * kRate;
    w.plane_wall(4).velocity = Vec3(0, 0, vz);
    w.plane_wall(5).velocity = Vec3(0, 0, -vz);
    for (long step = 0;; step += kServoEvery) {
        const double ea = (l0.z() - lengths(w).z()) / l0.z();
        if (step % kSampleEvery == 0) {
            const Vec3 s = wall_stress(w);
            const double q = s.z() - 0.5 * (s.x() + s.y()), pm = (s.x() + s.y() + s.z()) / 3.0;
            const double ev = (v0 - lengths(w).prod()) / v0;
            char b[256];
            std::snprintf(b, sizeof b, "%.6f,%.4f,%.6f,%.4f\n", 100 * ea, 1e-3 * q, 100 * ev, 1e-3 * pm);
            csv << b;
            csv.flush();
        }
        if (ea >= 0.1) break;
        servo(w, lateral);
        w.cycle(kServoEvery);
    }
    std::fprintf(stderr, "shear done: %ld steps\n", w.step());
    return 0;
}
