// The stored form of a snapshot: the fields as native little-endian binary, zlib-compressed
// (exact doubles; what the service keeps per run and stage, and the CLI in its run folder).
#include <cstring>

#include <zlib.h>

#include "server/io/packing_formats.hpp"

namespace triax::io {

using protocol::SpecimenSnapshot;

namespace {

constexpr char kMagic[4] = {'T', 'X', 'S', 'N'};
// Version 2 adds the particles' mass and inertia and the sizing radii (exact restart);
// version 1 is still read.
constexpr std::uint32_t kVersion = 2;

class Writer {
public:
    template <class T> void pod(const T& v) { bytes.append(reinterpret_cast<const char*>(&v), sizeof v); }
    void str(const std::string& s) {
        pod(static_cast<std::uint32_t>(s.size()));
        bytes += s;
    }
    template <class T> void array(const std::vector<T>& v) {
        pod(static_cast<std::uint64_t>(v.size()));
        if (!v.empty()) bytes.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
    }
    void vecs(const std::vector<Vec3>& v) {
        pod(static_cast<std::uint64_t>(v.size()));
        for (const auto& e : v) {
            pod(e.x());
            pod(e.y());
            pod(e.z());
        }
    }
    std::string bytes;
};

class Reader {
public:
    explicit Reader(const std::string& b) : b_(b) {}
    template <class T> T pod() {
        need(sizeof(T));
        T v;
        std::memcpy(&v, b_.data() + at_, sizeof v);
        at_ += sizeof v;
        return v;
    }
    std::string str() {
        const auto n = pod<std::uint32_t>();
        need(n);
        std::string s = b_.substr(at_, n);
        at_ += n;
        return s;
    }
    template <class T> std::vector<T> array() {
        const auto n = pod<std::uint64_t>();
        need(n * sizeof(T));
        std::vector<T> v(n);
        if (n) std::memcpy(v.data(), b_.data() + at_, n * sizeof(T));
        at_ += n * sizeof(T);
        return v;
    }
    std::vector<Vec3> vecs() {
        const auto n = pod<std::uint64_t>();
        need(n * 3 * sizeof(double));
        std::vector<Vec3> v(n);
        for (auto& e : v) {
            const double x = pod<double>(), y = pod<double>(), z = pod<double>();
            e = Vec3(x, y, z);
        }
        return v;
    }

private:
    void need(std::size_t n) const {
        if (at_ + n > b_.size()) throw std::runtime_error("stored snapshot is truncated");
    }
    const std::string& b_;
    std::size_t at_ = 0;
};

}  // namespace

std::string encode_snapshot(const SpecimenSnapshot& s) {
    Writer w;
    w.str(s.stage);
    w.pod(static_cast<std::int64_t>(s.step));
    w.vecs(s.position);
    w.array(s.radius);
    w.array(s.density);
    w.array(s.mass);
    w.array(s.inertia);
    w.array(s.group);
    w.vecs(s.velocity);
    w.vecs(s.angular_velocity);
    w.vecs(s.displacement);
    w.vecs(s.rotation);
    w.array(s.crushed);
    w.array(s.contact_i);
    w.array(s.contact_j);
    w.array(s.bonded);
    w.array(s.normal_force_n);
    w.vecs(s.shear_force_n);
    w.array(s.bond_normal_strength_n);
    w.array(s.bond_shear_strength_n);
    w.pod(static_cast<std::uint32_t>(s.platens.size()));
    for (const auto& p : s.platens) {
        w.str(p.name);
        w.vecs({p.point, p.normal});
        w.pod(p.normal_force_n);
    }
    w.pod(static_cast<std::uint32_t>(s.measurement_spheres.size()));
    for (const auto& m : s.measurement_spheres) {
        w.vecs({m.center});
        w.pod(m.radius_m);
    }
    w.pod(static_cast<std::uint32_t>(s.group_names.size()));
    for (const auto& g : s.group_names) w.str(g);
    w.pod(s.sizing_mean_radius_m);
    w.pod(s.sizing_min_radius_m);

    uLongf packed_size = compressBound(w.bytes.size());
    std::string out(sizeof kMagic + sizeof(std::uint32_t) + sizeof(std::uint64_t) + packed_size, '\0');
    std::memcpy(out.data(), kMagic, sizeof kMagic);
    std::memcpy(out.data() + 4, &kVersion, sizeof kVersion);
    const std::uint64_t raw = w.bytes.size();
    std::memcpy(out.data() + 8, &raw, sizeof raw);
    auto* dst = reinterpret_cast<Bytef*>(out.data() + 16);
    if (compress2(dst, &packed_size, reinterpret_cast<const Bytef*>(w.bytes.data()), w.bytes.size(), Z_BEST_SPEED) != Z_OK)
        throw std::runtime_error("compressing a snapshot failed");
    out.resize(16 + packed_size);
    return out;
}

SpecimenSnapshot decode_snapshot(const std::string& bytes) {
    if (bytes.size() < 16 || std::memcmp(bytes.data(), kMagic, 4) != 0)
        throw std::runtime_error("not a stored triax snapshot");
    std::uint32_t version = 0;
    std::memcpy(&version, bytes.data() + 4, sizeof version);
    if (version != 1 && version != kVersion) throw std::runtime_error("stored snapshot version " + std::to_string(version) + " is not supported");
    std::uint64_t raw_size = 0;
    std::memcpy(&raw_size, bytes.data() + 8, sizeof raw_size);
    std::string raw(raw_size, '\0');
    uLongf got = raw_size;
    if (uncompress(reinterpret_cast<Bytef*>(raw.data()), &got, reinterpret_cast<const Bytef*>(bytes.data() + 16),
                   bytes.size() - 16) != Z_OK ||
        got != raw_size)
        throw std::runtime_error("stored snapshot is corrupt");
    Reader r(raw);
    SpecimenSnapshot s;
    s.stage = r.str();
    s.step = static_cast<long>(r.pod<std::int64_t>());
    s.position = r.vecs();
    s.radius = r.array<double>();
    s.density = r.array<double>();
    if (version >= 2) {
        s.mass = r.array<double>();
        s.inertia = r.array<double>();
    }
    s.group = r.array<int>();
    s.velocity = r.vecs();
    s.angular_velocity = r.vecs();
    s.displacement = r.vecs();
    s.rotation = r.vecs();
    s.crushed = r.array<std::uint8_t>();
    s.contact_i = r.array<int>();
    s.contact_j = r.array<int>();
    s.bonded = r.array<std::uint8_t>();
    s.normal_force_n = r.array<double>();
    s.shear_force_n = r.vecs();
    s.bond_normal_strength_n = r.array<double>();
    s.bond_shear_strength_n = r.array<double>();
    const auto np = r.pod<std::uint32_t>();
    for (std::uint32_t k = 0; k < np; ++k) {
        protocol::SnapshotPlaten p;
        p.name = r.str();
        const auto v = r.vecs();
        if (v.size() != 2) throw std::runtime_error("stored snapshot is corrupt (platen)");
        p.point = v[0];
        p.normal = v[1];
        p.normal_force_n = r.pod<double>();
        s.platens.push_back(p);
    }
    const auto nm = r.pod<std::uint32_t>();
    for (std::uint32_t k = 0; k < nm; ++k) {
        const auto v = r.vecs();
        if (v.size() != 1) throw std::runtime_error("stored snapshot is corrupt (sphere)");
        s.measurement_spheres.push_back({v[0], r.pod<double>()});
    }
    const auto ng = r.pod<std::uint32_t>();
    for (std::uint32_t k = 0; k < ng; ++k) s.group_names.push_back(r.str());
    if (version >= 2) {
        s.sizing_mean_radius_m = r.pod<double>();
        s.sizing_min_radius_m = r.pod<double>();
    }
    return s;
}

}  // namespace triax::io
