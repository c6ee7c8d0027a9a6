// The membrane's share of a specimen step (never run by CI; docs/performance.md,
// "Membrane"). Generates the specimen of a paper group (reduced by default: 50 x 100 mm,
// the specimen of paper_group --reduced and of the protocol tests), frees the membrane and
// switches to the test laws, then times, per thread count:
//   specimen  Specimen::cycle (engine steps + the membrane's follower forces every few steps)
//   engine    World::cycle on the same world (the engine's part only)
//   no membrane  a World with the same soil spheres, laws and platens, the membrane replaced
//            by a rigid cylinder wall at its inner radius (what the step costs without it)
// and prints the particle and contact-slot counts by kind (soil-soil, soil-membrane,
// membrane-membrane; candidates and active), so the difference can be read per item.
//
// Usage: membrane_share [group=B] [steps=2000] [--full] [--threads LIST]  (LIST e.g. 1,2)
#include "engine/protocol/paper_groups.hpp"
#include "engine/protocol/specimen.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <sys/resource.h>

using namespace triax;

namespace {

double cpu_seconds() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_utime.tv_sec + 1e-6 * ru.ru_utime.tv_usec + ru.ru_stime.tv_sec + 1e-6 * ru.ru_stime.tv_usec;
}

// Wall and CPU seconds of f().
template <class F>
std::pair<double, double> timed(F&& f) {
    const double c0 = cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return {std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), cpu_seconds() - c0};
}

// The specimen's soil spheres, laws and platens, with a cylinder wall where the membrane was.
World without_membrane(protocol::Specimen& sp) {
    const World& a = sp.world();
    World b;
    const ContactLawTable& laws = a.contact_laws();
    b.set_default_contact_law(laws.get(protocol::kSoilGroup, protocol::kSoilGroup));
    b.set_contact_law(protocol::kSoilGroup, protocol::kPlatenGroup, laws.get(protocol::kSoilGroup, protocol::kPlatenGroup));
    // The cylinder takes the soil-membrane law.
    b.set_contact_law(protocol::kSoilGroup, protocol::kMembraneGroup, laws.get(protocol::kSoilGroup, protocol::kMembraneGroup));
    const ParticleArrays& pa = a.particles();
    for (std::size_t p = 0; p < pa.size(); ++p) {
        if (pa.group[p] != protocol::kSoilGroup) continue;
        const double density = pa.mass[p] / (4.0 / 3.0 * 3.14159265358979323846 * pa.radius[p] * pa.radius[p] * pa.radius[p]);
        const int q = b.add_sphere(pa.position[p], pa.radius[p], density, protocol::kSoilGroup);
        b.particles().velocity[q] = pa.velocity[p];
        b.particles().angular_velocity[q] = pa.angular_velocity[p];
    }
    for (std::size_t k = 0; k < a.plane_wall_count(); ++k) {
        const PlaneWall& w = a.plane_wall(static_cast<int>(k));
        b.add_plane_wall(w.point, w.normal, w.group);
    }
    const double z0 = sp.bottom_z(), z1 = sp.top_z();
    const double r_in = sp.membrane()->mean_inner_radius(a);
    b.add_cylinder_wall(Vec3(0, 0, z0), Vec3::UnitZ(), r_in, z1 - z0, protocol::kMembraneGroup);
    b.set_time_step(a.time_step());
    b.set_local_damping(a.local_damping());
    b.set_density_scaling(a.density_scaling());
    b.set_gravity(a.gravity());
    b.set_threads(a.threads());
    return b;
}

void count_slots(const World& w) {
    const ContactStore& c = w.contacts();
    const ParticleArrays& pa = w.particles();
    long cand[3] = {0, 0, 0}, active[3] = {0, 0, 0};
    for (std::size_t k = 0; k < c.size(); ++k) {
        const int kind = (pa.group[c.i[k]] == protocol::kMembraneGroup) + (pa.group[c.j[k]] == protocol::kMembraneGroup);
        ++cand[kind];
        active[kind] += c.active[k] != 0;
    }
    long membrane = 0;
    for (int g : pa.group) membrane += g == protocol::kMembraneGroup;
    std::printf("particles %zu (membrane %ld, %.1f %%); ball-ball slots: soil-soil %ld (active %ld), soil-membrane %ld "
                "(active %ld), membrane-membrane %ld (active %ld); wall slots %zu\n",
                pa.size(), membrane, 100.0 * membrane / pa.size(), cand[0], active[0], cand[1], active[1], cand[2],
                active[2], w.wall_contacts().size());
}

}  // namespace

int main(int argc, char** argv) {
    std::string group = "B";
    long steps = 2000;
    bool full = false;
    std::vector<int> threads = {1, 2};
    int positional = 0;
    for (int a = 1; a < argc; ++a) {
        const std::string arg = argv[a];
        if (arg == "--full") full = true;
        else if (arg == "--threads" && a + 1 < argc) {
            threads.clear();
            for (const char* s = argv[++a]; *s;) {
                char* end = nullptr;
                threads.push_back(static_cast<int>(std::strtol(s, &end, 10)));
                s = *end == ',' ? end + 1 : end;
            }
        } else if (positional == 0) { group = arg; ++positional; }
        else if (positional == 1) { steps = std::stol(arg); ++positional; }
    }
    protocol::TestScheme scheme = protocol::paper_group(group);
    if (!full) {
        // paper_group --reduced
        scheme.specimen.diameter_m = 0.05;
        scheme.specimen.height_m = 0.1;
        scheme.gradation.r_min_m = 2.5e-3;
        scheme.gradation.radius_ratio = 3.0;
        scheme.seed = 11;
    }
    scheme.threads = 1;
    const auto t0 = std::chrono::steady_clock::now();
    protocol::Specimen sp(scheme);
    sp.install_test_laws();
    sp.release_lateral_boundary();
    const double sigma3 = scheme.loading.confining_pressure_pa;
    sp.cycle(1000, sigma3);  // settle the freed membrane under the confining pressure
    std::printf("group %s %s specimen generated in %.0f s\n", group.c_str(), full ? "full-size" : "reduced",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    count_slots(sp.world());
    World bare = without_membrane(sp);
    bare.cycle(1000);
    std::printf("without membrane: ");
    count_slots(bare);
    for (int t : threads) {
        sp.world().set_threads(t);
        bare.set_threads(t);
        const double n_sp = static_cast<double>(sp.world().particle_count()) * steps;
        const double n_bare = static_cast<double>(bare.particle_count()) * steps;
        const auto a = timed([&] { sp.cycle(steps, sigma3); });
        const auto e = timed([&] { sp.world().cycle(steps); });
        const auto b = timed([&] { bare.cycle(steps); });
        std::printf("threads=%d, %ld steps: specimen %.3f s wall %.3f s CPU (%.1f us/step, %.3g particle-steps per CPU-s); "
                    "engine %.3f s wall %.3f s CPU (%.1f us/step); no membrane %.3f s wall %.3f s CPU (%.1f us/step, "
                    "%.3g particle-steps per CPU-s)\n",
                    t, steps, a.first, a.second, 1e6 * a.first / steps, n_sp / a.second, e.first, e.second,
                    1e6 * e.first / steps, b.first, b.second, 1e6 * b.first / steps, n_bare / b.second);
    }
    return 0;
}
