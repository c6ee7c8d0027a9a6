// The text forms of a snapshot (sphere list, LAMMPS data, legacy VTK) and the sphere-list
// reader. Doubles are written with max_digits10 digits: read back, they are the same bits.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>

#include "server/io/bounded_json.hpp"
#include "server/io/packing_formats.hpp"

namespace triax::io {

using protocol::SpecimenSnapshot;

namespace {

// Shortest text that reads back as the same double (std::to_chars round-trip form).
void put(std::string& out, double v) {
    char b[64];
    const auto r = std::to_chars(b, b + sizeof b, v);
    out.append(b, r.ptr);
}
void put(std::string& out, long v) { out += std::to_string(v); }
void put(std::string& out, int v) { out += std::to_string(v); }

std::string group_legend(const SpecimenSnapshot& s) {
    std::string g;
    for (std::size_t k = 0; k < s.group_names.size(); ++k)
        g += (k ? ", " : "") + std::to_string(k) + " " + s.group_names[k];
    return g;
}

std::string trim(const std::string& s) {
    std::size_t a = 0, b = s.size();
    while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
    while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
    return s.substr(a, b - a);
}

std::string lower(std::string s) {
    for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// Reads one number of a row; the whole token must be a number.
bool read_number(const std::string& tok, double& v) {
    const char* b = tok.data();
    const char* e = b + tok.size();
    if (b != e && *b == '+') ++b;
    const auto r = std::from_chars(b, e, v);
    return r.ec == std::errc() && r.ptr == e;
}

}  // namespace

std::string snapshot_sphere_list(const SpecimenSnapshot& s) {
    std::string out;
    out += "# triax sphere list: stage " + s.stage + ", " + std::to_string(s.particle_count()) + " spheres (group " +
           group_legend(s) + ")\n";
    out += "# units: m\n# x_m y_m z_m r_m group\n";
    for (std::size_t k = 0; k < s.particle_count(); ++k) {
        put(out, s.position[k].x());
        out += ' ';
        put(out, s.position[k].y());
        out += ' ';
        put(out, s.position[k].z());
        out += ' ';
        put(out, s.radius[k]);
        out += ' ';
        put(out, s.group[k]);
        out += '\n';
    }
    return out;
}

std::string snapshot_lammps_data(const SpecimenSnapshot& s) {
    const std::size_t n = s.particle_count();
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    int types = 1;
    for (std::size_t k = 0; k < n; ++k) {
        lo = lo.cwiseMin(s.position[k] - Vec3::Constant(s.radius[k]));
        hi = hi.cwiseMax(s.position[k] + Vec3::Constant(s.radius[k]));
        types = std::max(types, s.group[k] + 1);
    }
    if (n == 0) lo = hi = Vec3::Zero();
    // A margin of 5 % of the extent: the box must hold every sphere as it moves a little.
    const Vec3 margin = 0.05 * (hi - lo) + Vec3::Constant(1e-6);
    lo -= margin;
    hi += margin;
    std::string out = "LAMMPS data file: triax snapshot, stage " + s.stage + " (units si; atom_style sphere; type = group + 1: " +
                      group_legend(s) + ")\n\n";
    out += std::to_string(n) + " atoms\n" + std::to_string(types) + " atom types\n\n";
    const char* axes[3][2] = {{"xlo", "xhi"}, {"ylo", "yhi"}, {"zlo", "zhi"}};
    for (int a = 0; a < 3; ++a) {
        put(out, lo[a]);
        out += ' ';
        put(out, hi[a]);
        out += std::string(" ") + axes[a][0] + " " + axes[a][1] + "\n";
    }
    out += "\nAtoms # sphere\n\n";
    for (std::size_t k = 0; k < n; ++k) {
        put(out, static_cast<long>(k + 1));
        out += ' ';
        put(out, s.group[k] + 1);
        out += ' ';
        put(out, 2.0 * s.radius[k]);
        out += ' ';
        put(out, s.density[k]);
        for (int a = 0; a < 3; ++a) {
            out += ' ';
            put(out, s.position[k][a]);
        }
        out += '\n';
    }
    out += "\nVelocities\n\n";
    for (std::size_t k = 0; k < n; ++k) {
        put(out, static_cast<long>(k + 1));
        for (int a = 0; a < 3; ++a) {
            out += ' ';
            put(out, s.velocity[k][a]);
        }
        for (int a = 0; a < 3; ++a) {
            out += ' ';
            put(out, s.angular_velocity[k][a]);
        }
        out += '\n';
    }
    return out;
}

std::string snapshot_vtk(const SpecimenSnapshot& s) {
    const std::size_t n = s.particle_count(), m = s.contact_count();
    std::string out = "# vtk DataFile Version 3.0\n";
    out += "triax snapshot " + s.stage + " (SI: m, N, rad; group " + group_legend(s) + ")\n";
    out += "ASCII\nDATASET POLYDATA\nPOINTS " + std::to_string(n) + " double\n";
    for (std::size_t k = 0; k < n; ++k) {
        put(out, s.position[k].x());
        out += ' ';
        put(out, s.position[k].y());
        out += ' ';
        put(out, s.position[k].z());
        out += '\n';
    }
    if (m > 0) {
        out += "LINES " + std::to_string(m) + " " + std::to_string(3 * m) + "\n";
        for (std::size_t k = 0; k < m; ++k) out += "2 " + std::to_string(s.contact_i[k]) + " " + std::to_string(s.contact_j[k]) + "\n";
    }
    auto scalars = [&](const std::string& name, const char* type, std::size_t count, auto value) {
        out += "SCALARS " + name + " " + type + " 1\nLOOKUP_TABLE default\n";
        for (std::size_t k = 0; k < count; ++k) {
            put(out, value(k));
            out += '\n';
        }
    };
    out += "POINT_DATA " + std::to_string(n) + "\n";
    scalars("radius_m", "double", n, [&](std::size_t k) { return s.radius[k]; });
    scalars("group", "int", n, [&](std::size_t k) { return s.group[k]; });
    scalars("displacement_m", "double", n, [&](std::size_t k) { return s.displacement[k].norm(); });
    scalars("rotation_rad", "double", n, [&](std::size_t k) { return s.rotation[k].norm(); });
    scalars("crushed", "int", n, [&](std::size_t k) { return static_cast<int>(s.crushed[k]); });
    out += "VECTORS displacement_vector_m double\n";
    for (std::size_t k = 0; k < n; ++k) {
        put(out, s.displacement[k].x());
        out += ' ';
        put(out, s.displacement[k].y());
        out += ' ';
        put(out, s.displacement[k].z());
        out += '\n';
    }
    if (m > 0) {
        out += "CELL_DATA " + std::to_string(m) + "\n";
        scalars("normal_force_N", "double", m, [&](std::size_t k) { return s.normal_force_n[k]; });
        scalars("shear_force_N", "double", m, [&](std::size_t k) { return s.shear_force_n[k].norm(); });
        scalars("bonded", "int", m, [&](std::size_t k) { return static_cast<int>(s.bonded[k]); });
    }
    return out;
}

std::string snapshot_to_text(const SpecimenSnapshot& s, PackingFormat f) {
    switch (f) {
        case PackingFormat::Json: return snapshot_view_json(s).dump();
        case PackingFormat::Project: return snapshot_project_json(s).dump();
        case PackingFormat::Spheres: return snapshot_sphere_list(s);
        case PackingFormat::Lammps: return snapshot_lammps_data(s);
        case PackingFormat::Vtk: return snapshot_vtk(s);
    }
    return {};
}

protocol::ImportedPacking parse_sphere_list(const std::string& text, const std::string& source,
                                            const std::optional<std::string>& units) {
    std::optional<double> scale;  // file unit -> m
    std::string scale_from;
    auto set_unit = [&](const std::string& u, const std::string& from, int line) {
        double f = 0.0;
        if (u == "m") f = 1.0;
        else if (u == "mm") f = 1e-3;
        else throw PackingParseError(source + " line " + std::to_string(line) + ": unknown unit '" + u + "' (m or mm)", line);
        if (scale && *scale != f)
            throw PackingParseError(source + " line " + std::to_string(line) + ": unit " + u + " from " + from +
                                        " contradicts the unit from " + scale_from,
                                    line);
        scale = f;
        scale_from = from;
    };
    if (units) set_unit(*units, "the units parameter", 0);
    protocol::ImportedPacking p;
    p.source = source;
    std::istringstream in(text);
    std::string raw;
    int line = 0;
    while (std::getline(in, raw)) {
        ++line;
        const std::string t = trim(raw);
        if (t.empty()) continue;
        if (t[0] == '#') {
            std::string c = lower(trim(t.substr(1)));
            if (c.rfind("units:", 0) == 0 || c.rfind("units =", 0) == 0 || c.rfind("units=", 0) == 0) {
                const auto at = c.find_first_of(":=");
                set_unit(trim(c.substr(at + 1)), "line " + std::to_string(line), line);
            } else if (c.rfind("x_m ", 0) == 0 || c == "x_m") {
                set_unit("m", "the column header of line " + std::to_string(line), line);
            } else if (c.rfind("x_mm ", 0) == 0 || c == "x_mm") {
                set_unit("mm", "the column header of line " + std::to_string(line), line);
            }
            continue;
        }
        if (!scale)
            throw PackingParseError(source + " line " + std::to_string(line) +
                                        ": no unit stated before the first sphere; add a header line '# units: m' "
                                        "or '# units: mm' (or a column header '# x_m y_m z_m r_m group')",
                                    line);
        std::istringstream row(t);
        std::vector<std::string> tok;
        for (std::string w; row >> w;) tok.push_back(w);
        if (tok.size() != 4 && tok.size() != 5)
            throw PackingParseError(source + " line " + std::to_string(line) + ": expected 4 or 5 columns (x y z r [group]), got " +
                                        std::to_string(tok.size()),
                                    line);
        double v[5] = {0, 0, 0, 0, 0};
        const char* names[5] = {"x", "y", "z", "r", "group"};
        for (std::size_t c = 0; c < tok.size(); ++c)
            if (!read_number(tok[c], v[c]) || !std::isfinite(v[c]))
                throw PackingParseError(source + " line " + std::to_string(line) + ": column " + names[c] + " '" + tok[c] +
                                            "' is not a finite number",
                                        line);
        if (tok.size() == 5) {
            if (v[4] != std::floor(v[4]) || v[4] < 0 || v[4] > 2)
                throw PackingParseError(source + " line " + std::to_string(line) + ": group must be 0 (grain), 1 (membrane) or 2 "
                                                                                   "(platen); got " + tok[4],
                                        line);
        }
        if (v[3] <= 0.0)
            throw PackingParseError(source + " line " + std::to_string(line) + ": radius must be positive; got " + tok[3], line);
        if (v[4] == 2) continue;  // platens are planes, placed from the grains
        if (v[4] == 1) {          // an exported membrane, restored when it fits the scheme's lattice
            p.membrane_position.emplace_back(v[0] * *scale, v[1] * *scale, v[2] * *scale);
            p.membrane_radius.push_back(v[3] * *scale);
            continue;
        }
        p.position.emplace_back(v[0] * *scale, v[1] * *scale, v[2] * *scale);
        p.radius.push_back(v[3] * *scale);
        p.line.push_back(line);
    }
    if (p.size() == 0) throw PackingParseError(source + ": no grains (rows of group 0) in the file", 0);
    return p;
}

protocol::ImportedPacking parse_packing(const std::string& text, const std::string& source,
                                        const std::optional<std::string>& units) {
    const auto first = text.find_first_not_of(" \t\r\n");
    if (first != std::string::npos && text[first] == '{') {
        nlohmann::json j;
        try {
            j = parse_bounded_json(text);
        } catch (const JsonLimitError& e) {
            if (e.syntax && e.byte > 0)
                throw PackingParseError(source + ": not valid JSON (byte " + std::to_string(e.byte) + ")", 0, e.pointer);
            throw PackingParseError(source + ": " + e.what() + (e.pointer.empty() ? "" : " at " + e.pointer), 0, e.pointer);
        }
        try {
            return packing_from_project_json(j, source);
        } catch (const PackingParseError& e) {
            throw PackingParseError(source + ": " + e.what(), e.line, e.pointer);
        }
    }
    return parse_sphere_list(text, source, units);
}

}  // namespace triax::io
