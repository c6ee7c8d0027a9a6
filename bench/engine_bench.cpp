// Engine benchmark (never run by CI). Builds a dense packing of N spheres (radius
// ratio 3, like a packable version of the paper's gradation) by radius expansion in a
// rigid box, servo-compresses it isotropically to 100 kPa (frictionless, which gives
// the dense state), switches to mu = 0.4, then times 5,000 steps at 1 and 2 threads
// (median of several runs) and the time per step at N = 2k, 8k, 32k.
//
// Usage: engine_bench [N=10000] [steps=5000] [repeats=3] [options]
//   --packing FILE       reuse the servo-compressed packing stored in FILE (built and
//                        stored there when FILE does not exist): A/B runs of two builds
//                        then time the same state without the minutes of preparation
//   --threads LIST       thread counts to time, e.g. 1 or 2 or 1,2 (default 1,2)
//   --no-scaling         skip the 2k/8k/32k scaling runs
//   --lammps-data FILE   write the timed packing as a LAMMPS data file (atom_style sphere,
//                        box = the six walls) for bench/anchors/lammps_triax_packing.in
// The packing is the state at the end of the frictionless servo: shear forces are zero
// there and normal forces follow from the overlaps, so positions, velocities, spins,
// radii and walls are the whole state.
#include "engine/core/world.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <sys/resource.h>

using namespace triax;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDensity = 2650.0;  // kg/m^3
constexpr double kRmin = 1.0e-3, kRmax = 3.0e-3;  // m
constexpr double kKn = 1e6, kKs = 1e6;              // N/m
constexpr double kTargetSolidFraction = 0.645;      // expansion target (porosity ~0.355 before servo)

struct Rng {
    std::uint64_t s;
    explicit Rng(std::uint64_t seed) : s(seed * 2654435761ULL + 1) {}
    double uniform() {
        s ^= s << 13; s ^= s >> 7; s ^= s << 17;
        return static_cast<double>(s >> 11) * (1.0 / 9007199254740992.0);
    }
};

struct Box {
    double lo[3], hi[3];
};

double solid_volume(const World& w) {
    double v = 0.0;
    for (double r : w.particles().radius) v += 4.0 / 3.0 * kPi * r * r * r;
    return v;
}

double box_volume(World& w) {
    // walls 0..5: -x, +x, -y, +y, -z, +z
    return (w.plane_wall(1).point.x() - w.plane_wall(0).point.x()) *
           (w.plane_wall(3).point.y() - w.plane_wall(2).point.y()) *
           (w.plane_wall(5).point.z() - w.plane_wall(4).point.z());
}

void set_radius(World& w, std::size_t p, double r) {
    auto& pa = w.particles();
    pa.radius[p] = r;
    pa.mass[p] = kDensity * 4.0 / 3.0 * kPi * r * r * r;
    pa.inertia[p] = 0.4 * pa.mass[p] * r * r;
}

// Mean normal stress on the three pairs of walls (Pa, compression positive).
Vec3 wall_stress(World& w) {
    const double lx = w.plane_wall(1).point.x() - w.plane_wall(0).point.x();
    const double ly = w.plane_wall(3).point.y() - w.plane_wall(2).point.y();
    const double lz = w.plane_wall(5).point.z() - w.plane_wall(4).point.z();
    const double sx = 0.5 * (w.plane_wall(0).normal_stress(ly * lz) + w.plane_wall(1).normal_stress(ly * lz));
    const double sy = 0.5 * (w.plane_wall(2).normal_stress(lx * lz) + w.plane_wall(3).normal_stress(lx * lz));
    const double sz = 0.5 * (w.plane_wall(4).normal_stress(lx * ly) + w.plane_wall(5).normal_stress(lx * ly));
    return Vec3(sx, sy, sz);
}

// Lattice of spheres with final radii scaled down, then radius expansion to a solid
// fraction of 0.645, frictionless.
World loose_packing(int n, int threads) {
    World w;
    w.set_threads(threads);
    ContactLaw law;
    law.kn = kKn; law.ks = kKs; law.friction = 0.0;
    w.set_default_contact_law(law);
    const int side = static_cast<int>(std::ceil(std::cbrt(static_cast<double>(n))));
    const double a = 2.02 * kRmax;
    const double L = side * a;
    w.add_plane_wall(Vec3(0, 0, 0), Vec3::UnitX());
    w.add_plane_wall(Vec3(L, 0, 0), -Vec3::UnitX());
    w.add_plane_wall(Vec3(0, 0, 0), Vec3::UnitY());
    w.add_plane_wall(Vec3(0, L, 0), -Vec3::UnitY());
    w.add_plane_wall(Vec3(0, 0, 0), Vec3::UnitZ());
    w.add_plane_wall(Vec3(0, 0, L), -Vec3::UnitZ());
    Rng rng(12345);
    std::vector<double> target;
    for (int k = 0; k < n; ++k) {
        const int x = k % side, y = (k / side) % side, z = k / (side * side);
        const double r = kRmin + (kRmax - kRmin) * rng.uniform();
        target.push_back(r);
        w.add_sphere(Vec3((x + 0.5) * a, (y + 0.5) * a, (z + 0.5) * a), r, kDensity);
    }
    w.set_skin(0.2 * kRmin);
    w.set_time_step(0.2 * std::sqrt(kDensity * 4.0 / 3.0 * kPi * std::pow(kRmin, 3) / kKn));
    const double v_box = box_volume(w);
    for (int round = 0; round < 2000; ++round) {
        const double phi = solid_volume(w) / v_box;
        if (phi >= kTargetSolidFraction * (1 - 1e-6)) break;
        const double f = std::min(1.005, std::cbrt(kTargetSolidFraction / phi));
        for (std::size_t p = 0; p < w.particle_count(); ++p) set_radius(w, p, w.particles().radius[p] * f);
        w.invalidate_neighbors();
        w.cycle(50);
    }
    w.cycle(2000);  // settle
    return w;
}

// Servo the six walls to an isotropic stress (Pa).
void servo_to(World& w, double target, int max_rounds) {
    const double gain = 2e-6;  // m/s per Pa
    for (int round = 0; round < max_rounds; ++round) {
        const Vec3 s = wall_stress(w);
        for (int axis = 0; axis < 3; ++axis) {
            const double v = std::clamp(gain * (target - s[axis]), -0.05, 0.05);
            Vec3 dir = Vec3::Zero();
            dir[axis] = v;
            w.plane_wall(2 * axis).velocity = dir;
            w.plane_wall(2 * axis + 1).velocity = -dir;
        }
        w.cycle(50);
        const Vec3 now = wall_stress(w);
        if ((now.array() - target).abs().maxCoeff() < 0.01 * target && w.unbalanced_force_ratio() < 1e-3) break;
    }
    for (int k = 0; k < 6; ++k) w.plane_wall(k).velocity.setZero();
}

// Servo-compressed packing, frictionless law, as stored by --packing.
constexpr char kPackingMagic[8] = {'T', 'R', 'X', 'P', 'A', 'C', 'K', '1'};

// The file also holds the time step of the timed runs (0.5 x critical with the servo's
// contacts, which a freshly loaded world does not have yet).
bool read_packing(const std::string& path, int n, World& w, double& dt) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    char magic[8];
    std::int64_t count = 0;
    in.read(magic, 8);
    in.read(reinterpret_cast<char*>(&count), sizeof count);
    if (!in || std::memcmp(magic, kPackingMagic, 8) != 0 || count != n)
        throw InputError("--packing " + path + ": not a packing of N = " + std::to_string(n) + " (delete it to rebuild)");
    double walls[6];
    in.read(reinterpret_cast<char*>(walls), sizeof walls);
    in.read(reinterpret_cast<char*>(&dt), sizeof dt);
    ContactLaw law;
    law.kn = kKn; law.ks = kKs; law.friction = 0.0;
    w.set_default_contact_law(law);
    for (int k = 0; k < 6; ++k) {
        const int axis = k / 2;
        Vec3 point = Vec3::Zero(), normal = Vec3::Zero();
        point[axis] = walls[k];
        normal[axis] = k % 2 ? -1.0 : 1.0;
        w.add_plane_wall(point, normal);
    }
    for (std::int64_t p = 0; p < count; ++p) {
        double rec[10];
        in.read(reinterpret_cast<char*>(rec), sizeof rec);
        const int q = w.add_sphere(Vec3(rec[0], rec[1], rec[2]), rec[3], kDensity);
        set_radius(w, q, rec[3]);
        w.particles().velocity[q] = Vec3(rec[4], rec[5], rec[6]);
        w.particles().angular_velocity[q] = Vec3(rec[7], rec[8], rec[9]);
    }
    if (!in) throw InputError("--packing " + path + ": file is truncated");
    w.set_skin(0.2 * kRmin);
    return true;
}

void write_packing(const std::string& path, const World& w, double dt) {
    std::ofstream out(path, std::ios::binary);
    const std::int64_t count = static_cast<std::int64_t>(w.particle_count());
    out.write(kPackingMagic, 8);
    out.write(reinterpret_cast<const char*>(&count), sizeof count);
    for (int k = 0; k < 6; ++k) {
        const double x = w.plane_wall(k).point[k / 2];
        out.write(reinterpret_cast<const char*>(&x), sizeof x);
    }
    out.write(reinterpret_cast<const char*>(&dt), sizeof dt);
    const auto& pa = w.particles();
    for (std::size_t p = 0; p < pa.size(); ++p) {
        const double rec[10] = {pa.position[p].x(), pa.position[p].y(), pa.position[p].z(), pa.radius[p],
                                pa.velocity[p].x(), pa.velocity[p].y(), pa.velocity[p].z(),
                                pa.angular_velocity[p].x(), pa.angular_velocity[p].y(), pa.angular_velocity[p].z()};
        out.write(reinterpret_cast<const char*>(rec), sizeof rec);
    }
    if (!out) throw InputError("--packing " + path + ": cannot write");
}

// LAMMPS data file (atom_style sphere: id type diameter density x y z), the box = the walls.
void write_lammps_data(const std::string& path, const World& w) {
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (!f) throw InputError("--lammps-data " + path + ": cannot write");
    const auto& pa = w.particles();
    std::fprintf(f, "triax engine_bench packing (SI), walls at the box faces\n\n%zu atoms\n1 atom types\n\n", pa.size());
    const char* axis[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a)
        std::fprintf(f, "%.17g %.17g %slo %shi\n", w.plane_wall(2 * a).point[a], w.plane_wall(2 * a + 1).point[a], axis[a], axis[a]);
    std::fprintf(f, "\nAtoms # sphere\n\n");
    for (std::size_t p = 0; p < pa.size(); ++p)
        std::fprintf(f, "%zu 1 %.17g %.17g %.17g %.17g %.17g\n", p + 1, 2.0 * pa.radius[p], kDensity, pa.position[p].x(),
                     pa.position[p].y(), pa.position[p].z());
    std::fclose(f);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

double cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_utime.tv_sec + 1e-6 * u.ru_utime.tv_usec + u.ru_stime.tv_sec + 1e-6 * u.ru_stime.tv_usec;
}

// Wall seconds for `steps` steps; the CPU seconds (all threads) go to *cpu. On a
// shared machine the CPU time tells what the code costs, the wall time what you wait.
double seconds_for(World w, int threads, long steps, double* cpu = nullptr) {
    w.set_threads(threads);
    w.cycle(10);  // warm-up: thread pool, first rebuild
    const double c0 = cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    w.cycle(steps);
    const auto t1 = std::chrono::steady_clock::now();
    if (cpu) *cpu = cpu_seconds() - c0;
    return std::chrono::duration<double>(t1 - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> positional;
    std::string packing_path, lammps_path;
    std::vector<int> thread_counts = {1, 2};
    bool scaling = true;
    for (int a = 1; a < argc; ++a) {
        const std::string arg = argv[a];
        if (arg == "--packing" && a + 1 < argc) packing_path = argv[++a];
        else if (arg == "--lammps-data" && a + 1 < argc) lammps_path = argv[++a];
        else if (arg == "--no-scaling") scaling = false;
        else if (arg == "--threads" && a + 1 < argc) {
            thread_counts.clear();
            for (const char* s = argv[++a]; *s;) {
                char* end = nullptr;
                const long t = std::strtol(s, &end, 10);
                if (end == s || t < 1) {
                    std::fprintf(stderr, "engine_bench: --threads wants a list like 1,2\n");
                    return 2;
                }
                thread_counts.push_back(static_cast<int>(t));
                s = *end == ',' ? end + 1 : end;
            }
        } else if (arg.rfind("--", 0) == 0) {
            std::fprintf(stderr, "engine_bench: unknown option %s\n", arg.c_str());
            return 2;
        } else positional.push_back(arg);
    }
    const int n = positional.size() > 0 ? std::atoi(positional[0].c_str()) : 10000;
    const long steps = positional.size() > 1 ? std::atol(positional[1].c_str()) : 5000;
    const int repeats = positional.size() > 2 ? std::atoi(positional[2].c_str()) : 3;
    try {
        const auto t_prep = std::chrono::steady_clock::now();
        World w;
        double dt = 0.0;
        if (packing_path.empty() || !read_packing(packing_path, n, w, dt)) {
            w = loose_packing(n, 1);
            std::fprintf(stderr, "expanded: step %ld, porosity %.3f, contacts %ld\n", w.step(),
                         1.0 - solid_volume(w) / box_volume(w), w.active_contact_count());
            servo_to(w, 100e3, 600);
            std::fprintf(stderr, "servo done: step %ld\n", w.step());
            dt = w.critical_time_step(0.5);
            if (!packing_path.empty()) write_packing(packing_path, w, dt);
        }
        ContactLaw law;
        law.kn = kKn; law.ks = kKs; law.friction = 0.4;
        w.set_default_contact_law(law);
        w.set_time_step(dt);
        w.cycle(1000);
        const double porosity = 1.0 - solid_volume(w) / box_volume(w);
        const Vec3 s = wall_stress(w);
        std::printf("packing: N=%d, radius %.1f-%.1f mm, porosity %.3f, wall stress %.1f/%.1f/%.1f kPa, "
                    "contacts %ld, coordination %.2f, dt %.3g s, prep %.0f s\n",
                    n, kRmin * 1e3, kRmax * 1e3, porosity, s.x() / 1e3, s.y() / 1e3, s.z() / 1e3,
                    w.active_contact_count(), 2.0 * w.active_contact_count() / n, w.time_step(),
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t_prep).count());
        if (!lammps_path.empty()) write_lammps_data(lammps_path, w);
        for (int threads : thread_counts) {
            std::vector<double> runs, cpus;
            for (int r = 0; r < repeats; ++r) {
                double cpu = 0.0;
                runs.push_back(seconds_for(w, threads, steps, &cpu));
                cpus.push_back(cpu);
            }
            const double t = median(runs), c = median(cpus);
            std::printf("threads=%d: %ld steps in %.3f s wall (median of %d) -> %.3g particle-steps/s; "
                        "CPU %.3f s -> %.3g particle-steps per CPU-second\n",
                        threads, steps, t, repeats, n * static_cast<double>(steps) / t, c,
                        n * static_cast<double>(steps) / c);
            std::fflush(stdout);
        }
        // Scaling: quick packings (expansion only, frictionless) timed for a few hundred steps.
        for (int size : {2000, 8000, 32000}) {
            if (!scaling) break;
            World q = loose_packing(size, 1);
            law.friction = 0.4;
            q.set_default_contact_law(law);
            std::vector<double> runs, cpus;
            for (int r = 0; r < repeats; ++r) {
                double cpu = 0.0;
                runs.push_back(seconds_for(q, 2, 500, &cpu));
                cpus.push_back(cpu);
            }
            const double t = median(runs), c = median(cpus);
            std::printf("scaling: N=%d, 2 threads: %.3g s/step wall (%.3g us per particle-step), "
                        "%.3g CPU-us per particle-step, contacts %ld\n",
                        size, t / 500, t / 500 / size * 1e6, c / 500 / size * 1e6, q.active_contact_count());
            std::fflush(stdout);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "engine_bench: %s\n", e.what());
        return 1;
    }
    return 0;
}
