#include "server/scaleout/wire_format.hpp"

#include <cstring>
#include <stdexcept>

namespace triax::scaleout {

using namespace triax::diagnose;

namespace {

// Upper bound of any count on the wire: a corrupt count fails here with a message rather
// than as an allocation of petabytes.
constexpr std::uint64_t kMaxCount = std::uint64_t{1} << 40;

std::uint64_t count(WireReader& r, const char* what) {
    const auto n = r.u64(what);
    if (n > kMaxCount) throw std::runtime_error(std::string("wire format: count of ") + what + " out of range");
    return n;
}

}  // namespace

void WireReader::raw(void* p, std::size_t n, const char* what) {
    if (in_.size() - at_ < n) throw std::runtime_error(std::string("wire format: message ends inside ") + what);
    std::memcpy(p, in_.data() + at_, n);
    at_ += n;
}

std::uint64_t WireReader::u64(const char* what) {
    std::uint64_t v = 0;
    raw(&v, sizeof v, what);
    return v;
}

double WireReader::f64(const char* what) {
    double v = 0;
    raw(&v, sizeof v, what);
    return v;
}

std::string WireReader::bytes(const char* what) {
    const auto n = count(*this, what);
    if (in_.size() - at_ < n) throw std::runtime_error(std::string("wire format: message ends inside ") + what);
    std::string s(in_.substr(at_, n));
    at_ += n;
    return s;
}

std::vector<double> WireReader::doubles(const char* what) {
    const auto n = count(*this, what);
    if ((in_.size() - at_) / sizeof(double) < n)
        throw std::runtime_error(std::string("wire format: message ends inside ") + what);
    std::vector<double> v(n);
    if (n > 0) raw(v.data(), n * sizeof(double), what);
    return v;
}

std::string encode_request(const SimulationRequest& r) {
    WireWriter w;
    w.u64(r.seed);
    w.doubles(r.point.base);
    w.u64(r.point.effects.size());
    for (const auto& [effect, params] : r.point.effects) {
        w.u64(static_cast<std::uint64_t>(effect));
        w.doubles(params);
    }
    return w.take();
}

SimulationRequest decode_request(std::string_view bytes) {
    WireReader rd(bytes);
    SimulationRequest r;
    r.seed = rd.u64("seed");
    r.point.base = rd.doubles("base parameters");
    const auto n = count(rd, "effects");
    for (std::uint64_t i = 0; i < n; ++i) {
        const auto e = rd.u64("effect");
        if (e > static_cast<std::uint64_t>(Effect::MembraneCompliance))
            throw std::runtime_error("wire format: effect " + std::to_string(e) + " is not in the catalog");
        r.point.effects.emplace_back(static_cast<Effect>(e), rd.doubles("effect parameters"));
    }
    if (!rd.done()) throw std::runtime_error("wire format: bytes left after the request");
    return r;
}

void write_dataset(WireWriter& w, const LabDataset& d) {
    w.bytes(d.name);
    w.u64(d.curves.size());
    for (const auto& c : d.curves) {
        w.u64(c.kind == CurveKind::Creep ? 1 : 0);
        w.u64(static_cast<std::uint64_t>(static_cast<std::int64_t>(c.stage)));
        w.f64(c.confining_pa);
        w.f64(c.stress_level);
        for (const auto* col : {&c.time_s, &c.axial_strain, &c.axial_deformation_m, &c.deviator_pa, &c.volumetric_strain})
            w.doubles(*col);
    }
    w.u64(d.summary.size());
    for (const auto& s : d.summary) {
        w.bytes(s.specimen);
        for (double v : {s.confining_pa, s.deviator_at_failure_pa, s.strain_at_failure, s.moisture_content,
                         s.dry_density_kg_m3, s.cohesion_pa, s.friction_angle_deg})
            w.f64(v);
    }
}

LabDataset read_dataset(WireReader& r) {
    LabDataset d;
    d.name = r.bytes("dataset name");
    const auto n = count(r, "curves");
    for (std::uint64_t i = 0; i < n; ++i) {
        LabCurve c;
        c.kind = r.u64("curve kind") == 1 ? CurveKind::Creep : CurveKind::Shear;
        c.stage = static_cast<int>(static_cast<std::int64_t>(r.u64("stage")));
        c.confining_pa = r.f64("confining pressure");
        c.stress_level = r.f64("stress level");
        for (auto* col : {&c.time_s, &c.axial_strain, &c.axial_deformation_m, &c.deviator_pa, &c.volumetric_strain})
            *col = r.doubles("curve column");
        d.curves.push_back(std::move(c));
    }
    const auto m = count(r, "summary rows");
    for (std::uint64_t i = 0; i < m; ++i) {
        LabSummaryRow s;
        s.specimen = r.bytes("specimen");
        for (double* v : {&s.confining_pa, &s.deviator_at_failure_pa, &s.strain_at_failure, &s.moisture_content,
                          &s.dry_density_kg_m3, &s.cohesion_pa, &s.friction_angle_deg})
            *v = r.f64("summary value");
        d.summary.push_back(std::move(s));
    }
    return d;
}

std::string encode_outcome(const SimulationOutcome& o) {
    WireWriter w;
    w.u64(o.ok ? 1 : 0);
    if (o.ok) write_dataset(w, o.curves);
    else w.bytes(o.error);
    return w.take();
}

SimulationOutcome decode_outcome(std::string_view bytes) {
    WireReader rd(bytes);
    SimulationOutcome o;
    o.ok = rd.u64("ok flag") == 1;
    if (o.ok) o.curves = read_dataset(rd);
    else o.error = rd.bytes("error message");
    if (!rd.done()) throw std::runtime_error("wire format: bytes left after the outcome");
    return o;
}

}  // namespace triax::scaleout
