#pragma once
// Up-front resource checks of the front ends: what a run will need, compared
// with the memory it may take (--max-memory, by default half the machine's),
// before any work. Each estimate is a measured cost model (figures in
// docs/results-limits.md): a tool refuses with one line naming the option,
// the figure and the limit, e.g. "gim-remesh: --size 16385 needs ~231 GB for
// the image, its normals, remesh and measures (limit 11.7 GB, half the
// machine's memory); use --size 2049 or less, or raise --max-memory".
// Everything here throws Failure; nothing allocates what it checks.
#include "tool/tool.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace ism::tool {

/// Physical memory of the machine (sysconf), or the memory limit of the
/// control group the process runs in when that is smaller.
std::size_t machine_memory_bytes();

/// The default of --max-memory: half of machine_memory_bytes(), leaving
/// room for the system and a second run.
std::size_t default_memory_limit();

/// "8G", "8GB", "512M", "1.5g", "800000000" (bytes; K, M, G, T are powers of
/// 1024); nothing for anything else, zero or an overflow.
std::optional<std::size_t> parse_memory_size(std::string_view text);

/// A size for a message: "6.4 GB", "850 MB", "12 KB".
std::string format_bytes(double bytes);

/// Caps this process's address space (RLIMIT_AS, soft limit only) at
/// `limit` plus room for thread stacks and libraries, so that what the
/// estimates miss ends in std::bad_alloc, which run_main turns into one
/// line, instead of the machine's memory. Does nothing under AddressSanitizer
/// (its shadow memory is address space) or when a lower limit is in place.
void cap_address_space(std::size_t limit);

/// Throws Failure "TOOL: WHAT needs ~X (limit Y); ADVICE" when `bytes`
/// exceeds the run's memory limit.
void require_memory(const Run& run, double bytes, const std::string& what,
                    const std::string& advice);

/// Memory the tool named `tool` needs per face of its input surface (the
/// map's progressive meshes, variants and overlay; reading and checking
/// alone for other tools), from measurements.
double surface_bytes_per_face(const std::string& tool);

/// Before reading a surface: its declared size (io::peek_mesh_size, which
/// throws io::FileError for a file it cannot read) times the tool's cost per
/// face, against the run's limit.
void check_surface_file(const Run& run, const std::filesystem::path& path);

/// gim-remesh: an n x n image (2^k+1) with its normals, the remesh and the
/// measures against the input; refuses sizes that are not 2^k+1, 3 <= n <=
/// 32769, and sizes the limit cannot hold, naming the largest that fits.
void check_geometry_image(const Run& run, int size);

/// semireg: `base_faces` x 4^levels remesh faces, sampled and measured.
/// `source` names what fixes the base in the message ("--base-size 5000").
void check_semiregular(const Run& run, std::size_t base_faces, int levels,
                       const std::string& source);
/// semireg --base-size N: a base is a decimation of the surface, so N must
/// be below the surface's vertex count (the file's bound before reading,
/// the welded count after).
void check_base_size(const Run& run, std::size_t base_size, std::uint64_t surface_vertices,
                     const std::string& surface_file);
/// The same before reading, against the vertices the file declares; nothing
/// when the file cannot be peeked, declares more than it holds or has no
/// vertex lines (reading it will say why).
void check_base_size(const Run& run, std::size_t base_size, const std::string& surface_file);

/// torus-remesh: a columns x rows grid, its triangles, image and measures.
void check_torus_grid(const Run& run, int columns, int rows);

/// ism-genmesh: a generated mesh of about `faces` faces, written.
void check_generated_mesh(const Run& run, std::size_t faces);

/// Refuses an output whose extension is not one of `extensions` (lower
/// case, with the dot), listing them: "gim-remesh: out.txt: -o writes
/// OpenEXR; use .exr". Nothing for an empty path.
void require_extension(const Run& run, const std::string& option, const std::string& path,
                       std::initializer_list<const char*> extensions, const std::string& kind);

/// The same for a triangle mesh output: .obj, .ply, .off, .stl or .drc
/// (io::write_mesh_file).
void require_mesh_extension(const Run& run, const std::string& option, const std::string& path);

}  // namespace ism::tool
