#include "tool/limits.hpp"

#include "io/io.hpp"
#include "tool/failure.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#define ISM_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ISM_ADDRESS_SANITIZER 1
#endif
#endif
#ifndef ISM_ADDRESS_SANITIZER
#define ISM_ADDRESS_SANITIZER 0
#endif

namespace ism::tool {
namespace {

// Costs fitted to peak resident memory (/usr/bin/time) of the tools,
// rounded up; the runs are in docs/results-hostile.md.
constexpr double kMB = 1024.0 * 1024.0;
// A process with the image libraries loaded, before any mesh (gim-remesh
// and torus-remesh start at 130-150 MB).
constexpr double kBaseBytes = 200 * kMB;
// Per input face: reading and checking (ism-info: 1M faces 465 MB), and the
// map of a tool (gim-remesh, two map variants side by side: bunny's 69630
// faces 301 MB, sphere's 5120 186 MB, i.e. about 1.8 KB per face).
constexpr double kCheckBytesPerFace = 600;
constexpr double kMapBytesPerFace = 4000;
// Per pixel of a geometry image: the image and its normals (doubles), the
// remesh (a vertex and two triangles), and the measures against the input
// (surface samples and a search tree over the remesh's triangles): 513^2
// 357 MB, 1025^2 1.02 GB, 2049^2 3.67 GB, i.e. 860 bytes per pixel.
constexpr double kImageBytesPerPixel = 900;
// Per face of a semi-regular remesh (level 6 over 96 base faces: 173 MB,
// level 4: 26 MB, i.e. 407 bytes per face) and per point of a torus grid
// (two triangles; 1024^2 1.09 GB, 256^2 206 MB, i.e. 920 bytes per point),
// sampled, written and measured.
constexpr double kRemeshBytesPerFace = 450;
constexpr double kGridBytesPerPoint = 1000;
// Per face of a generated mesh, the mesh and OpenMesh's writer kernel
// (4M faces: 364 MB).
constexpr double kGeneratedBytesPerFace = 120;

// The largest geometry image size OpenEXR and the layout take: 2^15 + 1.
constexpr int kLargestImage = (1 << 15) + 1;

std::string limit_text(const Run& run) {
  const std::size_t limit = run.memory_limit();
  return "limit " + format_bytes(double(limit)) +
         (limit == default_memory_limit() ? ", half the machine's memory" : "");
}

// The memory limit of this process's control group, if any (a Slurm job or
// a container): its own cgroup's file, named in /proc/self/cgroup (v2
// "0::/path", v1 "N:memory:/path"), then the mount's root.
std::optional<std::size_t> cgroup_memory_limit() {
  std::vector<std::string> files;
  std::ifstream self("/proc/self/cgroup");
  for (std::string line; std::getline(self, line);) {
    if (line.rfind("0::", 0) == 0)
      files.push_back("/sys/fs/cgroup" + line.substr(3) + "/memory.max");
    const std::size_t memory = line.find(":memory:");
    if (memory != std::string::npos)
      files.push_back("/sys/fs/cgroup/memory" + line.substr(memory + 8) + "/memory.limit_in_bytes");
  }
  files.push_back("/sys/fs/cgroup/memory.max");
  files.push_back("/sys/fs/cgroup/memory/memory.limit_in_bytes");
  std::optional<std::size_t> limit;
  for (const std::string& file : files) {
    std::ifstream in(file);
    std::string word;
    // "max" (v2) or a huge number (v1) means none.
    if (in >> word && !word.empty() && std::isdigit(static_cast<unsigned char>(word[0])) &&
        word.size() < 20) {
      const std::size_t bytes = std::size_t(std::stoull(word));
      limit = limit ? std::min(*limit, bytes) : bytes;
    }
  }
  return limit;
}

}  // namespace

std::size_t machine_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  std::size_t bytes = pages > 0 && page > 0 ? std::size_t(pages) * std::size_t(page)
                                            : std::size_t(4) << 30;  // unknown: assume 4 GB
  if (const auto cgroup = cgroup_memory_limit()) bytes = std::min(bytes, *cgroup);
  return bytes;
}

std::size_t default_memory_limit() {
  return machine_memory_bytes() / 2;
}

std::optional<std::size_t> parse_memory_size(std::string_view text) {
  std::string s;
  for (char c : text)
    if (!std::isspace(static_cast<unsigned char>(c)))
      s += char(std::toupper(static_cast<unsigned char>(c)));
  if (s.size() >= 2 && s.back() == 'B' && std::isalpha(static_cast<unsigned char>(s[s.size() - 2])))
    s.pop_back();  // "GB" as "G"
  else if (!s.empty() && s.back() == 'B')
    s.pop_back();  // "800B"
  double unit = 1;
  if (!s.empty() && std::isalpha(static_cast<unsigned char>(s.back()))) {
    const char u = s.back();
    unit = u == 'K'   ? 1024.0
           : u == 'M' ? kMB
           : u == 'G' ? 1024 * kMB
           : u == 'T' ? 1024 * 1024 * kMB
                      : 0;
    if (unit == 0) return std::nullopt;
    s.pop_back();
  }
  if (s.empty()) return std::nullopt;
  char* end = nullptr;
  const double value = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || !(value > 0) || !std::isfinite(value)) return std::nullopt;
  const double bytes = value * unit;
  if (bytes < 1 || bytes > 9.0e18) return std::nullopt;
  return std::size_t(bytes);
}

std::string format_bytes(double bytes) {
  const char* units[] = {"bytes", "KB", "MB", "GB", "TB", "PB"};
  int u = 0;
  while (bytes >= 1024 && u < 5) bytes /= 1024, ++u;
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, bytes < 10 && u > 0 ? "%.1f %s" : "%.0f %s", bytes,
                units[u]);
  return buffer;
}

void cap_address_space(std::size_t limit) {
#if ISM_ADDRESS_SANITIZER
  (void)limit;
#else
  // Thread stacks, malloc arenas and mapped libraries take address space
  // that is never resident: allow for them on top of the limit.
  const rlim_t wanted = rlim_t(limit) + (rlim_t(2) << 30);
  rlimit current{};
  if (::getrlimit(RLIMIT_AS, &current) != 0) return;
  if (current.rlim_cur != RLIM_INFINITY && current.rlim_cur <= wanted) return;
  current.rlim_cur =
      current.rlim_max == RLIM_INFINITY ? wanted : std::min(wanted, current.rlim_max);
  ::setrlimit(RLIMIT_AS, &current);
#endif
}

void require_memory(const Run& run, double bytes, const std::string& what,
                    const std::string& advice) {
  if (bytes <= double(run.memory_limit())) return;
  throw Failure(run.tool_name() + ": " + what + " needs ~" + format_bytes(bytes) + " (" +
                limit_text(run) + "); " + advice);
}

double surface_bytes_per_face(const std::string& tool) {
  return tool == "gim-remesh" || tool == "semireg" || tool == "torus-remesh" ? kMapBytesPerFace
                                                                             : kCheckBytesPerFace;
}

void check_surface_file(const Run& run, const std::filesystem::path& path) {
  const io::MeshFileSize size = io::peek_mesh_size(path);
  const double bytes = kBaseBytes + surface_bytes_per_face(run.tool_name()) * double(size.faces) +
                       2.0 * double(size.bytes);
  require_memory(run, bytes,
                 path.string() + " (" + std::to_string(size.faces) + " faces, " +
                     format_bytes(double(size.bytes)) + ")",
                 "simplify the mesh or raise --max-memory");
}

void check_geometry_image(const Run& run, int size) {
  if (size < 3 || size > kLargestImage || ((size - 1) & (size - 2)) != 0)
    throw Failure(run.tool_name() + ": --size must be 2^k+1 between 3 and " +
                  std::to_string(kLargestImage) + " (e.g. 65, 129, 257, 513), got " +
                  std::to_string(size));
  auto bytes = [](double n) { return kBaseBytes + kImageBytesPerPixel * n * n; };
  int largest = 0;
  for (int n = 3; n <= kLargestImage && bytes(n) <= double(run.memory_limit()); n = 2 * n - 1)
    largest = n;
  require_memory(
      run, bytes(size),
      "--size " + std::to_string(size) + " (the image, its normals, the remesh and its measures)",
      largest > 0 ? "use --size " + std::to_string(largest) + " or less, or raise --max-memory"
                  : "raise --max-memory");
}

void check_semiregular(const Run& run, std::size_t base_faces, int levels,
                       const std::string& source) {
  const double faces = double(base_faces) * std::pow(4.0, levels);
  int fitting = levels;
  while (fitting > 0 &&
         kBaseBytes + kRemeshBytesPerFace * double(base_faces) * std::pow(4.0, fitting) >
             double(run.memory_limit()))
    --fitting;
  char count[32];
  std::snprintf(count, sizeof count, "%.3g", faces);
  require_memory(
      run, kBaseBytes + kRemeshBytesPerFace * faces,
      source + " at --levels " + std::to_string(levels) + " (" + count + " remesh faces)",
      fitting < levels ? "use --levels " + std::to_string(fitting) +
                             " or less, a smaller base, or raise --max-memory"
                       : "use a smaller base or raise --max-memory");
}

void check_base_size(const Run& run, std::size_t base_size, std::uint64_t surface_vertices,
                     const std::string& surface_file) {
  if (base_size < surface_vertices) return;
  const std::string advice =
      surface_vertices > 4 ? "use --base-size " + std::to_string(surface_vertices - 1) + " or less"
                           : "a base has at least 4 vertices, so this surface is too small for one";
  throw Failure(run.tool_name() + ": --base-size " + std::to_string(base_size) + " is not below " +
                surface_file + "'s " + std::to_string(surface_vertices) +
                " vertices; a base decimates the surface (" + advice + ")");
}

void check_base_size(const Run& run, std::size_t base_size, const std::string& surface_file) {
  io::MeshFileSize size;
  try {
    size = io::peek_mesh_size(surface_file);
  } catch (const io::FileError&) {
    return;
  }
  // A corrupt header or a file without vertex lines: reading it says why.
  if (size.capped || size.vertices == 0) return;
  check_base_size(run, base_size, size.vertices, surface_file);
}

void check_torus_grid(const Run& run, int columns, int rows) {
  const double points = double(columns) * double(rows);
  require_memory(run, kBaseBytes + kGridBytesPerPoint * points,
                 "--size " + std::to_string(columns) + "x" + std::to_string(rows) +
                     " (the grid, its triangles, image and measures)",
                 "use a smaller --size or raise --max-memory");
}

void check_generated_mesh(const Run& run, std::size_t faces) {
  require_memory(run, kBaseBytes + kGeneratedBytesPerFace * double(faces),
                 "--faces " + std::to_string(faces), "use fewer --faces or raise --max-memory");
}

void require_extension(const Run& run, const std::string& option, const std::string& path,
                       std::initializer_list<const char*> extensions, const std::string& kind) {
  if (path.empty()) return;
  const std::string ext = std::filesystem::path(path).extension().string();
  for (const char* e : extensions)
    if (ext == e) return;
  std::string list;
  for (const char* e : extensions) list += std::string(list.empty() ? "" : ", ") + e;
  throw Failure(run.tool_name() + ": " + path + ": " + option + " writes " + kind + "; use " +
                list + (ext.empty() ? "" : " (not " + ext + ")"));
}

void require_mesh_extension(const Run& run, const std::string& option, const std::string& path) {
  require_extension(run, option, path, {".obj", ".ply", ".off", ".stl", ".drc", ".glb"}, "a mesh");
}

}  // namespace ism::tool
