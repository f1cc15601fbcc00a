#include "tool/tool.hpp"

#include "io/io.hpp"
#include "report/report.hpp"
#include "tool/failure.hpp"
#include "tool/limits.hpp"

#include <sys/resource.h>

#include <cstdio>
#include <fstream>

namespace ism::tool {
namespace {

// The limit of the last Run, for the out-of-memory line of run_main.
std::size_t last_memory_limit = 0;

}  // namespace

std::size_t peak_memory_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return std::size_t(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

Run::Run(std::string tool_name, CommonOptions options)
    : tool_(std::move(tool_name)),
      options_(std::move(options)),
      start_(std::chrono::steady_clock::now()),
      progress_(tool_, options_.quiet) {
  memory_limit_ = options_.max_memory ? options_.max_memory : default_memory_limit();
  last_memory_limit = memory_limit_;
  if (options_.cap_address_space) cap_address_space(memory_limit_);
  report_["tool"] = tool_;
  report_["version"] = ISM_VERSION;
  // Fail before the work, not after it, when the report cannot be written.
  if (!options_.report_path.empty()) check_output(options_.report_path);
  require_extension(*this, "--report", options_.report_path, {".json"}, "JSON");
}

void Run::add_input(const std::filesystem::path& path) {
  inputs_.push_back(path);
  if (!options_.report_path.empty()) check_output(options_.report_path);
}

void Run::check_output(const std::filesystem::path& path) const {
  OutputFile probe(path, inputs_);
}

Failure reading_failure(const std::filesystem::path& path, const std::exception& error) {
  std::error_code ec;
  const bool readable = std::filesystem::is_regular_file(path, ec) && std::ifstream(path).good();
  return Failure(error.what(), readable ? Failure::Kind::input : Failure::Kind::file);
}

TriangleMesh Run::load_surface(const std::filesystem::path& path, const MeshRequirements& needs,
                               MeshCheck* check) {
  return load_surface(InputMesh{path.string(), std::nullopt}, needs, check);
}

TriangleMesh Run::load_surface(const InputMesh& given, const MeshRequirements& needs,
                               MeshCheck* check) {
  PreparedMesh prepared = load_prepared(given, needs);
  if (check) *check = prepared.check;
  return std::move(prepared.mesh);
}

PreparedMesh Run::load_prepared(const InputMesh& given, const MeshRequirements& needs,
                                PolygonSoup* kept) {
  const std::filesystem::path path = given.path;
  PolygonSoup soup;
  if (given.soup) {
    soup = *given.soup;
  } else {
    add_input(path);
    stage("read");
    try {
      check_surface_file(*this, path);
      soup = io::read_polygon_soup(path);
    } catch (const io::FileError& e) {
      throw reading_failure(path, e);
    }
  }
  stage("check");
  PreparedMesh prepared = prepare_mesh(soup);
  Json input = Json::object();
  input["file"] = path.string();
  input["check"] = to_json(prepared.check);
  report_["inputs"].push_back(input);
  if (auto unmet = unmet_requirement(prepared.check, needs))
    throw Failure(path.string() + ": " + *unmet);
  for (const auto& repair : prepared.check.repairs()) note(path.string() + ": " + repair);
  for (const auto& warning : prepared.check.warnings())
    note(path.string() + ": warning: " + warning);
  if (kept) *kept = std::move(soup);
  return prepared;
}

Progress& Run::stage(const std::string& name) {
  end_stage();
  stage_name_ = name;
  stage_start_ = std::chrono::steady_clock::now();
  progress_.start(name);
  return progress_;
}

void Run::end_stage() {
  if (stage_name_.empty()) return;
  progress_.finish();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - stage_start_).count();
  Json& slot = stages_[stage_name_];
  slot = slot.is_null() ? Json(seconds) : slot;  // a repeated stage keeps its first timing
  // The process's peak so far: a stage whose figure exceeds the one before
  // raised the peak (a repeated stage keeps its first figure, as its time).
  Json& peak = stage_peaks_[stage_name_];
  if (peak.is_null()) peak = double(peak_memory_bytes()) / (1024.0 * 1024.0);
  stage_name_.clear();
}

void Run::note(const std::string& message) const {
  if (!options_.quiet) std::fprintf(stderr, "%s\n", message.c_str());
}

void Run::finish() {
  end_stage();
  report_["seconds"] = stages_;
  report_["seconds"]["total"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  report_["peak_memory_mb"] = double(peak_memory_bytes()) / (1024.0 * 1024.0);
  report_["peak_memory_mb_by_stage"] = stage_peaks_;
  if (options_.report_path.empty()) return;
  OutputFile out(options_.report_path, inputs_);
  {
    std::ofstream file(out.temp_path());
    file << report_text(report_) << '\n';
    if (!file)
      throw Failure(options_.report_path + ": cannot write the report", Failure::Kind::file);
  }
  out.commit();
}

void write_output(const Run& run, const std::string& path,
                  const std::function<void(const std::filesystem::path&)>& write) {
  if (path.empty()) return;
  OutputFile out(path, run.inputs());
  try {
    write(out.temp_path());
  } catch (const io::FileError& e) {
    // The writer names the temporary file: say the user's path instead.
    std::string why = e.what();
    const std::string temp = out.temp_path().string();
    for (std::size_t at; (at = why.find(temp)) != std::string::npos;)
      why.replace(at, temp.size(), path);
    throw Failure(why.rfind(path, 0) == 0 ? why : path + ": cannot write the file (" + why + ")",
                  Failure::Kind::file);
  }
  out.commit();
}

namespace {

// No allocation here: the message is built in a fixed buffer.
void out_of_memory(const std::string& tool_name) {
  char line[256];
  std::snprintf(line, sizeof line,
                "%s: out of memory (peak %.0f MB so far, limit %.0f MB); ask for smaller outputs "
                "or raise --max-memory\n",
                tool_name.c_str(), double(peak_memory_bytes()) / (1024.0 * 1024.0),
                double(last_memory_limit) / (1024.0 * 1024.0));
  std::fputs(line, stderr);
}

}  // namespace

int run_main(const std::string& tool_name, const std::function<int()>& body) {
  try {
    return body();
  } catch (const Failure& e) {
    std::fprintf(stderr, "%s\n", e.what());
  } catch (const std::bad_alloc&) {
    out_of_memory(tool_name);
  } catch (const std::length_error&) {
    out_of_memory(tool_name);  // a size computed beyond what can be allocated
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", tool_name.c_str(), e.what());
  }
  return 1;
}

}  // namespace ism::tool
