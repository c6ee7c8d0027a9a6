// The JSON forms of a snapshot: the page's view (lab units) and the complete project JSON
// (SI, exact), and the project JSON read back as a snapshot or as an imported packing.
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "server/io/packing_formats.hpp"

namespace triax::io {

using nlohmann::json;
using protocol::SpecimenSnapshot;

namespace {

constexpr const char* kProjectFormat = "triax-packing";
constexpr int kProjectVersion = 1;

// The view is drawn, not re-imported: lengths to 0.01 um and forces to 6 digits keep it small.
double quantize(double x, double quantum) { return std::round(x / quantum) * quantum; }
double six_digits(double x) {
    if (x == 0.0 || !std::isfinite(x)) return x;
    const double q = std::pow(10.0, std::floor(std::log10(std::abs(x))) - 5.0);
    return quantize(x, q);
}

json vec_json(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

Vec3 vec_from(const json& j, const std::string& what) {
    if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
        throw PackingParseError(what + " must be an array of 3 numbers", 0);
    return Vec3(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
}

// "particles" -> "/particles"; the where-names of this file are the top-level members.
std::string pointer_of(const std::string& where, const std::string& name) { return "/" + where + "/" + name; }

const json& field(const json& obj, const std::string& name, const std::string& where) {
    if (!obj.is_object() || !obj.contains(name))
        throw PackingParseError(where + ": missing field '" + name + "'", 0, pointer_of(where, name));
    return obj.at(name);
}

// An optional member of an object with the type the reader needs, or a refusal naming it
// (a null or a string where a number belongs is the sender's error, not ours).
std::string optional_text(const json& obj, const std::string& name, const std::string& pointer) {
    if (!obj.contains(name)) return {};
    if (!obj.at(name).is_string()) throw PackingParseError("field " + name + " must be a string", 0, pointer);
    return obj.at(name).get<std::string>();
}
double optional_number(const json& obj, const std::string& name, const std::string& pointer) {
    if (!obj.contains(name)) return 0.0;
    if (!obj.at(name).is_number()) throw PackingParseError("field " + name + " must be a number", 0, pointer);
    return obj.at(name).get<double>();
}
long optional_integer(const json& obj, const std::string& name, const std::string& pointer) {
    if (!obj.contains(name)) return 0;
    const json& v = obj.at(name);
    if (!v.is_number_integer() || (v.is_number_unsigned() && v.get<std::uint64_t>() > 0x7fffffffffffffffULL))
        throw PackingParseError("field " + name + " must be an integer", 0, pointer);
    return v.get<long>();
}
const json& optional_array(const json& obj, const std::string& name) {
    static const json empty = json::array();
    if (!obj.contains(name)) return empty;
    if (!obj.at(name).is_array()) throw PackingParseError("field " + name + " must be an array", 0, "/" + name);
    return obj.at(name);
}

template <class T>
std::vector<T> column(const json& obj, const std::string& name, const std::string& where, std::size_t n, bool required = true) {
    if (!obj.contains(name)) {
        if (required) throw PackingParseError(where + ": missing field '" + name + "'", 0);
        return {};
    }
    const json& a = obj.at(name);
    const std::string at = pointer_of(where, name);
    if (!a.is_array()) throw PackingParseError(where + "." + name + " must be an array", 0, at);
    if (a.size() != n)
        throw PackingParseError(where + "." + name + " has " + std::to_string(a.size()) + " entries; expected " +
                                    std::to_string(n),
                                0, at);
    std::vector<T> out;
    out.reserve(n);
    for (std::size_t k = 0; k < n; ++k) {
        if (!a[k].is_number())
            throw PackingParseError(where + "." + name + "[" + std::to_string(k) + "] is not a number", 0,
                                    at + "/" + std::to_string(k));
        if constexpr (std::is_integral_v<T>) {
            // An index or a flag: an integer that fits (a double beyond int would be UB to convert).
            const bool fits = a[k].is_number_integer() && a[k].get<double>() >= std::numeric_limits<T>::min() &&
                              a[k].get<double>() <= std::numeric_limits<T>::max();
            if (!fits)
                throw PackingParseError(where + "." + name + "[" + std::to_string(k) + "] is not an integer in range",
                                        0, at + "/" + std::to_string(k));
        }
        out.push_back(a[k].get<T>());
    }
    return out;
}

std::vector<Vec3> vec_columns(const json& obj, const std::string& x, const std::string& y, const std::string& z,
                              const std::string& where, std::size_t n, bool required = true) {
    const auto a = column<double>(obj, x, where, n, required), b = column<double>(obj, y, where, n, required),
               c = column<double>(obj, z, where, n, required);
    if (a.empty() || b.empty() || c.empty()) return {};
    std::vector<Vec3> out(n);
    for (std::size_t k = 0; k < n; ++k) out[k] = Vec3(a[k], b[k], c[k]);
    return out;
}

}  // namespace

std::optional<PackingFormat> packing_format_from_name(const std::string& name) {
    if (name == "json") return PackingFormat::Json;
    if (name == "project") return PackingFormat::Project;
    if (name == "spheres") return PackingFormat::Spheres;
    if (name == "lammps") return PackingFormat::Lammps;
    if (name == "vtk") return PackingFormat::Vtk;
    return std::nullopt;
}

const char* packing_format_name(PackingFormat f) {
    switch (f) {
        case PackingFormat::Json: return "json";
        case PackingFormat::Project: return "project";
        case PackingFormat::Spheres: return "spheres";
        case PackingFormat::Lammps: return "lammps";
        case PackingFormat::Vtk: return "vtk";
    }
    return "json";
}

const char* packing_content_type(PackingFormat f) {
    return f == PackingFormat::Json || f == PackingFormat::Project ? "application/json" : "text/plain";
}

const char* packing_file_extension(PackingFormat f) {
    switch (f) {
        case PackingFormat::Json: return ".view.json";
        case PackingFormat::Project: return ".packing.json";
        case PackingFormat::Spheres: return ".spheres.txt";
        case PackingFormat::Lammps: return ".data";
        case PackingFormat::Vtk: return ".vtk";
    }
    return ".txt";
}

json snapshot_counts_json(const SpecimenSnapshot& s) {
    return {{"stage", s.stage},
            {"grains", s.count_of(0)},
            {"membrane_particles", s.count_of(1)},
            {"contacts", s.contact_count()}};
}

json snapshot_view_json(const SpecimenSnapshot& s) {
    const std::size_t n = s.particle_count(), m = s.contact_count();
    constexpr double kMmQuantum = 1e-5;  // mm
    json x = json::array(), y = json::array(), z = json::array(), r = json::array(), g = json::array(),
         d = json::array(), rot = json::array(), cr = json::array();
    for (std::size_t k = 0; k < n; ++k) {
        x.push_back(quantize(1e3 * s.position[k].x(), kMmQuantum));
        y.push_back(quantize(1e3 * s.position[k].y(), kMmQuantum));
        z.push_back(quantize(1e3 * s.position[k].z(), kMmQuantum));
        r.push_back(quantize(1e3 * s.radius[k], kMmQuantum));
        g.push_back(s.group[k]);
        d.push_back(quantize(1e3 * s.displacement[k].norm(), kMmQuantum));
        rot.push_back(six_digits(s.rotation[k].norm()));
        cr.push_back(static_cast<int>(s.crushed[k]));
    }
    json ci = json::array(), cj = json::array(), fn = json::array(), fs = json::array(), b = json::array();
    for (std::size_t k = 0; k < m; ++k) {
        ci.push_back(s.contact_i[k]);
        cj.push_back(s.contact_j[k]);
        fn.push_back(six_digits(s.normal_force_n[k]));
        fs.push_back(six_digits(s.shear_force_n[k].norm()));
        b.push_back(static_cast<int>(s.bonded[k]));
    }
    json groups = json::object();
    for (std::size_t k = 0; k < s.group_names.size(); ++k) groups[std::to_string(k)] = s.group_names[k];
    json spheres = json::array();
    for (const auto& ms : s.measurement_spheres)
        spheres.push_back({{"center_mm", vec_json(1e3 * ms.center)}, {"radius_mm", 1e3 * ms.radius_m}});
    json platens = json::array();
    for (const auto& p : s.platens)
        platens.push_back({{"name", p.name},
                           {"point_mm", vec_json(1e3 * p.point)},
                           {"normal", vec_json(p.normal)},
                           {"normal_force_N", p.normal_force_n}});
    return {{"stage", s.stage},
            {"step", s.step},
            {"particles",
             {{"x_mm", x}, {"y_mm", y}, {"z_mm", z}, {"radius_mm", r}, {"group", g}, {"displacement_mm", d},
              {"rotation_rad", rot}, {"crushed", cr}}},
            {"groups", groups},
            {"contacts", {{"i", ci}, {"j", cj}, {"normal_force_N", fn}, {"shear_force_N", fs}, {"bonded", b}}},
            {"measurement_spheres", spheres},
            {"platens", platens}};
}

json snapshot_project_json(const SpecimenSnapshot& s) {
    json P = json::object();
    auto put_vec = [&](json& obj, const std::vector<Vec3>& v, const char* a, const char* b, const char* c) {
        json xa = json::array(), xb = json::array(), xc = json::array();
        for (const auto& e : v) {
            xa.push_back(e.x());
            xb.push_back(e.y());
            xc.push_back(e.z());
        }
        obj[a] = std::move(xa);
        obj[b] = std::move(xb);
        obj[c] = std::move(xc);
    };
    put_vec(P, s.position, "x_m", "y_m", "z_m");
    P["radius_m"] = s.radius;
    P["group"] = s.group;
    P["density_kg_m3"] = s.density;
    if (s.mass.size() == s.radius.size()) P["mass_kg"] = s.mass;
    if (s.inertia.size() == s.radius.size()) P["inertia_kg_m2"] = s.inertia;
    put_vec(P, s.velocity, "vx_m_s", "vy_m_s", "vz_m_s");
    put_vec(P, s.angular_velocity, "wx_rad_s", "wy_rad_s", "wz_rad_s");
    put_vec(P, s.displacement, "dx_m", "dy_m", "dz_m");
    put_vec(P, s.rotation, "rotation_x_rad", "rotation_y_rad", "rotation_z_rad");
    P["crushed"] = json::array();
    for (auto c : s.crushed) P["crushed"].push_back(static_cast<int>(c));
    json C = json::object();
    C["i"] = s.contact_i;
    C["j"] = s.contact_j;
    C["bonded"] = json::array();
    for (auto b : s.bonded) C["bonded"].push_back(static_cast<int>(b));
    C["normal_force_N"] = s.normal_force_n;
    put_vec(C, s.shear_force_n, "shear_x_N", "shear_y_N", "shear_z_N");
    C["bond_normal_strength_N"] = s.bond_normal_strength_n;
    C["bond_shear_strength_N"] = s.bond_shear_strength_n;
    json platens = json::array();
    for (const auto& p : s.platens)
        platens.push_back({{"name", p.name}, {"point_m", vec_json(p.point)}, {"normal", vec_json(p.normal)},
                           {"normal_force_N", p.normal_force_n}});
    json spheres = json::array();
    for (const auto& ms : s.measurement_spheres) spheres.push_back({{"center_m", vec_json(ms.center)}, {"radius_m", ms.radius_m}});
    return {{"format", kProjectFormat}, {"version", kProjectVersion}, {"units", "SI"},
            {"stage", s.stage},         {"step", s.step},              {"groups", s.group_names},
            {"particles", P},           {"contacts", C},               {"platens", platens},
            {"measurement_spheres", spheres}, {"sizing_mean_radius_m", s.sizing_mean_radius_m},
            {"sizing_min_radius_m", s.sizing_min_radius_m}};
}

namespace {
void check_project_header(const json& j) {
    if (!j.is_object()) throw PackingParseError("the project JSON must be an object", 0);
    if (!j.contains("format") || !j["format"].is_string() || j["format"].get<std::string>() != kProjectFormat)
        throw PackingParseError("field format must be \"" + std::string(kProjectFormat) + "\" (a triax project packing)",
                                0, "/format");
    if (!j.contains("units"))
        throw PackingParseError("missing field 'units': state the unit system (\"SI\": lengths in m, forces in N)", 0,
                                "/units");
    if (!j["units"].is_string() || j["units"].get<std::string>() != "SI")
        throw PackingParseError("field units must be \"SI\" (lengths in m, forces in N)", 0, "/units");
}
}  // namespace

SpecimenSnapshot snapshot_from_project_json(const json& j) {
    check_project_header(j);
    SpecimenSnapshot s;
    s.stage = optional_text(j, "stage", "/stage");
    s.step = optional_integer(j, "step", "/step");
    for (const char* key : {"sizing_mean_radius_m", "sizing_min_radius_m"})
        if (j.contains(key) && !(j[key].is_number() && j[key].get<double>() >= 0.0 && std::isfinite(j[key].get<double>())))
            throw PackingParseError(std::string("field ") + key + " must be a number >= 0 (m)", 0, std::string("/") + key);
    s.sizing_mean_radius_m = optional_number(j, "sizing_mean_radius_m", "/sizing_mean_radius_m");
    s.sizing_min_radius_m = optional_number(j, "sizing_min_radius_m", "/sizing_min_radius_m");
    const json& groups = optional_array(j, "groups");
    for (std::size_t k = 0; k < groups.size(); ++k) {
        if (!groups[k].is_string()) throw PackingParseError("groups[" + std::to_string(k) + "] must be a string", 0,
                                                            "/groups/" + std::to_string(k));
        s.group_names.push_back(groups[k].get<std::string>());
    }
    const json& P = field(j, "particles", "packing");
    const std::size_t n = field(P, "x_m", "particles").size();
    s.position = vec_columns(P, "x_m", "y_m", "z_m", "particles", n);
    s.radius = column<double>(P, "radius_m", "particles", n);
    s.group = column<int>(P, "group", "particles", n);
    s.density = column<double>(P, "density_kg_m3", "particles", n);
    s.mass = column<double>(P, "mass_kg", "particles", n, false);
    s.inertia = column<double>(P, "inertia_kg_m2", "particles", n, false);
    auto opt_vec = [&](const char* a, const char* b, const char* c) {
        auto v = vec_columns(P, a, b, c, "particles", n, false);
        if (v.empty()) v.assign(n, Vec3::Zero());
        return v;
    };
    s.velocity = opt_vec("vx_m_s", "vy_m_s", "vz_m_s");
    s.angular_velocity = opt_vec("wx_rad_s", "wy_rad_s", "wz_rad_s");
    s.displacement = opt_vec("dx_m", "dy_m", "dz_m");
    s.rotation = opt_vec("rotation_x_rad", "rotation_y_rad", "rotation_z_rad");
    for (int c : column<int>(P, "crushed", "particles", n, false)) s.crushed.push_back(static_cast<std::uint8_t>(c));
    if (s.crushed.empty()) s.crushed.assign(n, 0);
    if (j.contains("contacts")) {
        const json& C = j["contacts"];
        const std::size_t m = field(C, "i", "contacts").size();
        s.contact_i = column<int>(C, "i", "contacts", m);
        s.contact_j = column<int>(C, "j", "contacts", m);
        for (int b : column<int>(C, "bonded", "contacts", m)) s.bonded.push_back(static_cast<std::uint8_t>(b));
        s.normal_force_n = column<double>(C, "normal_force_N", "contacts", m);
        s.shear_force_n = vec_columns(C, "shear_x_N", "shear_y_N", "shear_z_N", "contacts", m);
        s.bond_normal_strength_n = column<double>(C, "bond_normal_strength_N", "contacts", m);
        s.bond_shear_strength_n = column<double>(C, "bond_shear_strength_N", "contacts", m);
        for (std::size_t k = 0; k < m; ++k)
            if (s.contact_i[k] < 0 || s.contact_j[k] < 0 || static_cast<std::size_t>(s.contact_i[k]) >= n ||
                static_cast<std::size_t>(s.contact_j[k]) >= n)
                throw PackingParseError("contacts[" + std::to_string(k) + "] names a particle outside 0.." +
                                            std::to_string(n == 0 ? 0 : n - 1),
                                        0);
    }
    const json& platens = optional_array(j, "platens");
    for (std::size_t k = 0; k < platens.size(); ++k) {
        const json& p = platens[k];
        const std::string at = "/platens/" + std::to_string(k);
        if (!p.is_object()) throw PackingParseError("platens[" + std::to_string(k) + "] must be an object", 0, at);
        s.platens.push_back({optional_text(p, "name", at + "/name"), vec_from(field(p, "point_m", "platens"), "platens.point_m"),
                             vec_from(field(p, "normal", "platens"), "platens.normal"),
                             optional_number(p, "normal_force_N", at + "/normal_force_N")});
    }
    const json& spheres = optional_array(j, "measurement_spheres");
    for (std::size_t k = 0; k < spheres.size(); ++k) {
        const json& ms = spheres[k];
        const std::string at = "/measurement_spheres/" + std::to_string(k);
        if (!ms.is_object()) throw PackingParseError("measurement_spheres[" + std::to_string(k) + "] must be an object", 0, at);
        if (!field(ms, "radius_m", "measurement_spheres").is_number())
            throw PackingParseError("measurement_spheres[" + std::to_string(k) + "].radius_m must be a number", 0, at + "/radius_m");
        s.measurement_spheres.push_back({vec_from(field(ms, "center_m", "measurement_spheres"), "measurement_spheres.center_m"),
                                         ms.at("radius_m").get<double>()});
    }
    return s;
}

protocol::ImportedPacking packing_from_project_json(const json& j, const std::string& source) {
    const SpecimenSnapshot s = snapshot_from_project_json(j);
    // The line each grain was read from, when the packing was converted from a sphere list.
    const auto lines = column<int>(j["particles"], "source_line", "particles", s.particle_count(), false);
    protocol::ImportedPacking p;
    p.source = source;
    for (std::size_t k = 0; k < s.particle_count(); ++k) {
        if (s.group[k] == 1) {  // an exported membrane, restored when it fits the scheme's lattice
            p.membrane_position.push_back(s.position[k]);
            p.membrane_radius.push_back(s.radius[k]);
        }
        if (s.group[k] != 0) continue;
        p.position.push_back(s.position[k]);
        p.radius.push_back(s.radius[k]);
        p.velocity.push_back(s.velocity[k]);
        p.angular_velocity.push_back(s.angular_velocity[k]);
        if (s.mass.size() == s.particle_count() && s.inertia.size() == s.particle_count()) {
            p.mass.push_back(s.mass[k]);
            p.inertia.push_back(s.inertia[k]);
        }
        p.line.push_back(k < lines.size() ? lines[k] : 0);
    }
    if (p.size() == 0) throw PackingParseError("the project JSON holds no grains (group 0)", 0);
    p.mean_radius_m = s.sizing_mean_radius_m;
    p.min_radius_m = s.sizing_min_radius_m;
    if (s.platens.size() == 2 && s.platens[0].name == "bottom" && s.platens[1].name == "top") {
        p.platen_force_n = {s.platens[0].normal_force_n, s.platens[1].normal_force_n};
        // Packings stored without the platens' heights wrote both points at the origin.
        if (s.platens[0].point.z() < s.platens[1].point.z()) p.platen_z_m = {s.platens[0].point.z(), s.platens[1].point.z()};
    }
    return p;
}

json packing_to_project_json(const protocol::ImportedPacking& p) {
    SpecimenSnapshot s;
    s.stage = "imported";
    s.group_names = {"grain"};
    s.sizing_mean_radius_m = p.mean_radius_m;
    s.sizing_min_radius_m = p.min_radius_m;
    // Grains, then the membrane's spheres (group 1; their mass is the rebuilt lattice's, 0 here).
    const std::size_t g = p.size(), n = g + p.membrane_position.size();
    s.position = p.position;
    s.position.insert(s.position.end(), p.membrane_position.begin(), p.membrane_position.end());
    s.radius = p.radius;
    s.radius.insert(s.radius.end(), p.membrane_radius.begin(), p.membrane_radius.end());
    s.group.assign(g, 0);
    s.group.resize(n, 1);
    s.density.assign(n, 0.0);
    if (p.mass.size() == g && p.inertia.size() == g) {
        s.mass = p.mass;
        s.inertia = p.inertia;
        s.mass.resize(n, 0.0);
        s.inertia.resize(n, 0.0);
    }
    if (n > g) s.group_names = {"grain", "membrane"};
    s.velocity = p.velocity.size() == g ? p.velocity : std::vector<Vec3>(g, Vec3::Zero());
    s.velocity.resize(n, Vec3::Zero());
    s.angular_velocity = p.angular_velocity.size() == g ? p.angular_velocity : std::vector<Vec3>(g, Vec3::Zero());
    s.angular_velocity.resize(n, Vec3::Zero());
    s.displacement.assign(n, Vec3::Zero());
    s.rotation.assign(n, Vec3::Zero());
    s.crushed.assign(n, 0);
    if (p.platen_force_n.size() == 2 || p.platen_z_m.size() == 2) {
        const bool force = p.platen_force_n.size() == 2, at = p.platen_z_m.size() == 2;
        s.platens.push_back({"bottom", at ? Vec3(0, 0, p.platen_z_m[0]) : Vec3::Zero(), Vec3::UnitZ(), force ? p.platen_force_n[0] : 0.0});
        s.platens.push_back({"top", at ? Vec3(0, 0, p.platen_z_m[1]) : Vec3::Zero(), -Vec3::UnitZ(), force ? p.platen_force_n[1] : 0.0});
    }
    json out = snapshot_project_json(s);
    if (p.line.size() == g) {
        std::vector<int> lines = p.line;
        lines.resize(n, 0);
        out["particles"]["source_line"] = lines;
    }
    return out;
}

}  // namespace triax::io
