#pragma once
// Packings in and out (docs/packings.md): a SpecimenSnapshot written in the formats other
// codes and viewers read, the compact stored form, and the readers that turn a sphere list
// or the project JSON into an ImportedPacking.
//
//   json     the page's view (lab units: mm, N), compression-positive normal force
//   project  the complete project JSON (SI, every double written to round-trip exactly):
//            grains, membrane, bonds, platens, contacts; what `triax run --packing` reads
//   spheres  "# x_m y_m z_m r_m group" text, SI (YADE's ymport.text reads the first 4 columns)
//   lammps   LAMMPS data file, atom_style sphere (id type diameter density x y z), units si
//   vtk      legacy VTK POLYDATA (ASCII): particles as POINTS with POINT_DATA, contacts as
//            LINES with CELL_DATA; SI
//
// Every double of the text formats is written with max_digits10 significant digits, so a
// file read back gives the same bits.
#include <optional>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/protocol/imported_packing.hpp"
#include "engine/protocol/specimen_snapshot.hpp"

namespace triax::io {

enum class PackingFormat { Json, Project, Spheres, Lammps, Vtk };

std::optional<PackingFormat> packing_format_from_name(const std::string& name);
const char* packing_format_name(PackingFormat f);
const char* packing_content_type(PackingFormat f);
const char* packing_file_extension(PackingFormat f);  // ".json", ".txt", ".data", ".vtk"

// A file that cannot become a packing: what is wrong, and where (line 0 = the whole file;
// `pointer`: the JSON pointer of the faulty value of a project JSON, empty when unknown).
struct PackingParseError : std::invalid_argument {
    int line = 0;
    std::string pointer;
    PackingParseError(const std::string& what, int line_no, std::string at = {})
        : std::invalid_argument(what), line(line_no), pointer(std::move(at)) {}
};

// ---- out ---------------------------------------------------------------------------
nlohmann::json snapshot_view_json(const protocol::SpecimenSnapshot& s);     // format json
nlohmann::json snapshot_project_json(const protocol::SpecimenSnapshot& s);  // format project
std::string snapshot_sphere_list(const protocol::SpecimenSnapshot& s);
std::string snapshot_lammps_data(const protocol::SpecimenSnapshot& s);
std::string snapshot_vtk(const protocol::SpecimenSnapshot& s);
// Any format as the text to serve or write.
std::string snapshot_to_text(const protocol::SpecimenSnapshot& s, PackingFormat f);

// The list entry of a stored snapshot: {"stage", "grains", "membrane_particles", "contacts"}.
nlohmann::json snapshot_counts_json(const protocol::SpecimenSnapshot& s);

// Project JSON -> snapshot (every field; the inverse of snapshot_project_json).
protocol::SpecimenSnapshot snapshot_from_project_json(const nlohmann::json& j);

// ---- stored form -----------------------------------------------------------------------
// Binary (native doubles, little-endian), zlib-compressed: exact and about 80 bytes per
// particle and 60 per contact before compression.
std::string encode_snapshot(const protocol::SpecimenSnapshot& s);
protocol::SpecimenSnapshot decode_snapshot(const std::string& bytes);

// ---- in -----------------------------------------------------------------------------------
// A sphere list: one sphere per line, "x y z r [group]", '#' comments, blank lines skipped.
// The unit comes from a header ("# units: m" / "mm", or a column header "# x_m ..." /
// "# x_mm ...") or from `units` ("m" or "mm"); a file with neither is refused. Rows of group
// 1 (membrane) and 2 (platen) are skipped: the membrane and the platens are rebuilt from the
// scheme. Errors name the line.
protocol::ImportedPacking parse_sphere_list(const std::string& text, const std::string& source,
                                            const std::optional<std::string>& units = std::nullopt);
// The project JSON (format project): its grains (group 0) with their velocities.
protocol::ImportedPacking packing_from_project_json(const nlohmann::json& j, const std::string& source);
// Either, told apart by the first non-blank character ('{' = project JSON). The JSON is read
// under the limits of every JSON body (io::parse_bounded_json: depth, string length,
// duplicate keys, numbers beyond a double), each refusal naming its pointer.
protocol::ImportedPacking parse_packing(const std::string& text, const std::string& source,
                                        const std::optional<std::string>& units = std::nullopt);

// An ImportedPacking as the project JSON (grains only), the form the service stores.
nlohmann::json packing_to_project_json(const protocol::ImportedPacking& p);

}  // namespace triax::io
