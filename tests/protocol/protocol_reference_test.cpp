// Stored reference trajectories of the protocol: a refactor that claims "behaviour
// unchanged" must leave these digests bitwise equal.
//
// Each run is short (a few seconds): a reduced specimen generated, consolidated, sheared
// to 0.5 % axial strain and held for one short creep stage. At the end of every stage the
// observer's stage_ended() digests the raw bits of every particle's position and force
// and both platens' positions; after the run the reported curves (shear, creep, energy and
// measurement samples, summary numbers) are digested too. The digests are FNV-1a 64 over
// the IEEE bits, so any change of any bit anywhere in the trajectory changes them.
//
// The bits depend on the compiler and its flags (TRIAX_NATIVE compiles for the build
// machine's CPU: FMA contraction changes the last bits). When a change of the physics is
// intended, or the toolchain changes, run
//   TRIAX_PRINT_REFERENCE=1 build/tests/test_protocol "[reference]"
// and paste the printed digests here, saying in the commit why they changed.
#include <catch2/catch.hpp>

#include <bit>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <string>
#include <vector>

#include "engine/core/world.hpp"
#include "engine/protocol/paper_groups.hpp"
#include "engine/protocol/triaxial_test.hpp"
#include "tests/support/reduced_specimen.hpp"

using namespace triax;
using namespace triax::protocol;

namespace {

class Digest {
public:
    void add(double x) { add_bits(std::bit_cast<std::uint64_t>(x)); }
    void add(long x) { add_bits(static_cast<std::uint64_t>(x)); }
    void add(int x) { add_bits(static_cast<std::uint64_t>(static_cast<std::int64_t>(x))); }
    void add(bool x) { add_bits(x ? 1u : 0u); }
    void add(const Vec3& v) {
        add(v.x());
        add(v.y());
        add(v.z());
    }
    std::uint64_t value() const { return h_; }

private:
    void add_bits(std::uint64_t b) {
        for (int k = 0; k < 8; ++k) {
            h_ ^= (b >> (8 * k)) & 0xffu;
            h_ *= 0x100000001b3ull;
        }
    }
    std::uint64_t h_ = 0xcbf29ce484222325ull;
};

struct StageDigest {
    std::string stage;
    long step = 0;
    std::uint64_t state = 0;
};

// Digests positions and forces of every particle and both platens' positions at each stage end.
class StateRecorder : public RunObserver {
public:
    void stage_ended(const std::string& stage, const World& w) override {
        Digest d;
        const auto& p = w.particles();
        for (std::size_t i = 0; i < p.position.size(); ++i) {
            d.add(p.position[i]);
            d.add(p.force[i]);
        }
        for (std::size_t k = 0; k < w.plane_wall_count(); ++k) d.add(w.plane_wall(static_cast<int>(k)).point);
        stages.push_back({stage, w.step(), d.value()});
    }
    std::vector<StageDigest> stages;
};

// Digest of everything the run reports.
std::uint64_t result_digest(const TestResult& r) {
    Digest d;
    d.add(r.particle_count);
    d.add(r.membrane_particle_count);
    d.add(r.initial_porosity);
    d.add(r.consolidation.porosity);
    d.add(r.consolidation.unbalanced_force_ratio);
    d.add(r.consolidation.steps);
    d.add(r.consolidation.achieved_sigma3_pa);
    for (const auto& p : r.shear) {
        d.add(p.axial_strain);
        d.add(p.q_pa);
        d.add(p.volumetric_strain);
        d.add(p.inertial_number);
    }
    d.add(r.q_failure_pa);
    d.add(r.axial_strain_at_failure);
    for (const auto& st : r.creep_stages) {
        for (const auto& p : st.raw) {
            d.add(p.time_s);
            d.add(p.axial_deformation_m);
        }
        for (const auto& p : st.translated) {
            d.add(p.time_s);
            d.add(p.axial_deformation_m);
        }
        d.add(st.q_pa);
        d.add(st.converged);
        d.add(st.accelerating);
        d.add(st.ruptured);
    }
    for (const auto& e : r.energies) {
        d.add(e.step);
        d.add(e.strain_j);
        d.add(e.slip_j);
        d.add(e.damping_j);
        d.add(e.kinetic_j);
        d.add(e.bond_j);
        d.add(e.boundary_work_j);
        d.add(e.creep_j);
        d.add(e.breakage_j);
    }
    for (const auto& m : r.measurements) {
        d.add(m.z_displacement_m);
        d.add(m.rotation_rate_x_rad_s);
        d.add(m.rotation_rate_y_rad_s);
        d.add(m.rotation_rate_z_rad_s);
        d.add(m.porosity);
        d.add(m.coordination);
    }
    d.add(r.total_steps);
    d.add(r.creep_relaxations);
    return d.value();
}

struct Reference {
    std::vector<StageDigest> stages;
    std::uint64_t result = 0;
};

void check_against(const char* name, const TestScheme& scheme, const Reference& ref) {
    StateRecorder rec;
    const TestResult r = run_triaxial_test(scheme, rec, Phase::Creep);
    const std::uint64_t result = result_digest(r);
    if (std::getenv("TRIAX_PRINT_REFERENCE") != nullptr) {
        std::printf("%s:\n", name);
        for (const auto& s : rec.stages)
            std::printf("    {\"%s\", %ld, 0x%016llxull},\n", s.stage.c_str(), s.step,
                        static_cast<unsigned long long>(s.state));
        std::printf("    result 0x%016llxull\n", static_cast<unsigned long long>(result));
    }
    INFO(name);
    REQUIRE(rec.stages.size() == ref.stages.size());
    for (std::size_t k = 0; k < ref.stages.size(); ++k) {
        INFO("stage " << ref.stages[k].stage);
        CHECK(rec.stages[k].stage == ref.stages[k].stage);
        CHECK(rec.stages[k].step == ref.stages[k].step);
        CHECK(rec.stages[k].state == ref.stages[k].state);
    }
    CHECK(result == ref.result);
}

// Short versions of a scheme: 0.5 % of shear and one creep stage of a minute.
void shorten(TestScheme& s, double stress_level) {
    s.loading.max_axial_strain = 0.005;
    s.loading.stress_levels = {stress_level};
    s.loading.stage_durations_s = {60.0};
    s.creep.first_increment_s = 5.0;
    s.creep.increment_growth = 1.5;
    s.creep.max_increment_s = 30.0;
}

}  // namespace

TEST_CASE("reference trajectory: scheme defaults on the reduced specimen", "[protocol][reference]") {
    TestScheme s = testing::reduced_scheme(2.5e-3, 0.005, 7);
    shorten(s, 0.6);
    check_against("defaults", s,
                  {{
                       {"generation", 8550, 0xd0715dde6d70f20dull},
                       {"consolidation", 34600, 0x8118101d78ac9477ull},
                       {"shear", 38500, 0x5d5f175810a6e75bull},
                       {"creep-1", 52600, 0xbb254f28e6a35e41ull},
                   },
                   0x835cb2bfc2660f87ull});
}

TEST_CASE("reference trajectory: paper group B on the reduced specimen", "[protocol][reference]") {
    // The preset's micro-parameters, creep law and loading on the reduced specimen.
    TestScheme s = paper_group("B");
    const TestScheme reduced = testing::reduced_scheme(2.5e-3, 0.005, 3);
    s.specimen = reduced.specimen;
    s.gradation = reduced.gradation;
    s.seed = reduced.seed;
    shorten(s, 0.6);
    check_against("group B", s,
                  {{
                       {"generation", 7800, 0x1989df4cd9d3baf0ull},
                       {"consolidation", 62300, 0xd530f0a0d01dc59eull},
                       {"shear", 66150, 0x59991aa2160d076eull},
                       {"creep-1", 72500, 0x2356102d0b834b11ull},
                   },
                   0x9eb8bf631732945dull});
}
