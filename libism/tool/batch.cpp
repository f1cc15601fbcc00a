#include "tool/batch.hpp"

#include "tool/child_process.hpp"
#include "tool/failure.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

namespace ism::tool {

namespace fs = std::filesystem;
using OrderedJson = nlohmann::ordered_json;

Shard parse_shard(const std::string& text) {
  const std::size_t slash = text.find('/');
  auto fail = [&](const std::string& why) { throw Failure("--shard " + text + ": " + why); };
  if (slash == std::string::npos) fail("expected i/n, e.g. 0/4");
  Shard s;
  try {
    std::size_t used = 0;
    s.index = std::stoi(text.substr(0, slash), &used);
    if (used != slash) fail("expected i/n, e.g. 0/4");
    const std::string count = text.substr(slash + 1);
    s.count = std::stoi(count, &used);
    if (used != count.size()) fail("expected i/n, e.g. 0/4");
  } catch (const std::logic_error&) {
    fail("expected i/n, e.g. 0/4");
  }
  if (s.count < 1) fail("the number of shards must be at least 1");
  if (s.index < 0 || s.index >= s.count)
    fail("the shard index must be in 0.." + std::to_string(s.count - 1) + " (Slurm: --array=0-" +
         std::to_string(s.count - 1) + ")");
  return s;
}

std::vector<BatchEntry> read_batch_list(const fs::path& list) {
  std::ifstream in(list);
  if (!in) throw Failure(list.string() + ": cannot read the list of meshes");
  std::vector<BatchEntry> entries;
  std::map<std::string, int> line_of_name;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    const std::string where = list.string() + ":" + std::to_string(number) + ": ";
    BatchEntry e;
    const std::size_t tab = line.find('\t', first);
    std::string path = line.substr(first, tab == std::string::npos ? tab : tab - first);
    while (!path.empty() && path.back() == ' ') path.pop_back();
    e.path = fs::absolute(path);
    e.name = tab == std::string::npos ? e.path.stem().string() : line.substr(tab + 1);
    if (e.name.empty() || e.name == "." || e.name == ".." || e.name.front() == '.' ||
        e.name.find_first_of("/\t\n") != std::string::npos)
      throw Failure(where + "'" + e.name +
                    "' cannot name an output folder (a plain file name not starting with '.')");
    const auto [it, fresh] = line_of_name.emplace(e.name, number);
    if (!fresh)
      throw Failure(where + "the name '" + e.name + "' is also on line " +
                    std::to_string(it->second) + "; give distinct names as PATH<TAB>NAME");
    entries.push_back(std::move(e));
  }
  if (entries.empty()) throw Failure(list.string() + ": no meshes in the list");
  return entries;
}

// ---- results file ----------------------------------------------------------

namespace {

// An exclusive fcntl lock on DIR/.results.lock for the lifetime of the object.
class ResultsLock {
 public:
  explicit ResultsLock(const fs::path& lock) {
    fd_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw Failure(lock.string() + ": cannot open the lock file");
    struct flock fl {};
    fl.l_type = F_WRLCK;
    fl.l_whence = SEEK_SET;
    while (::fcntl(fd_, F_SETLKW, &fl) != 0) {
      if (errno != EINTR) {
        ::close(fd_);
        throw Failure(lock.string() + ": cannot lock (" + std::strerror(errno) + ")");
      }
    }
  }
  ~ResultsLock() { ::close(fd_); }  // closing releases the lock
  ResultsLock(const ResultsLock&) = delete;
  ResultsLock& operator=(const ResultsLock&) = delete;

 private:
  int fd_ = -1;
};

std::string line_name(const std::string& line) {
  try {
    const auto j = nlohmann::json::parse(line);
    if (j.is_object() && j.contains("name") && j["name"].is_string()) return j["name"];
  } catch (const nlohmann::json::exception&) {
  }
  return {};
}

void write_fully(int fd, const std::string& text, const fs::path& path) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw Failure(path.string() + ": cannot write (" + std::strerror(errno) + ")");
    done += std::size_t(n);
  }
}

}  // namespace

ResultsFile::ResultsFile(fs::path dir)
    : dir_(std::move(dir)), path_(dir_ / "results.jsonl"), lock_(dir_ / ".results.lock") {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (!fs::is_directory(dir_)) throw Failure(dir_.string() + ": cannot create the output folder");
}

std::set<std::string> ResultsFile::names() const {
  ResultsLock lock(lock_);
  std::set<std::string> names;
  std::ifstream in(path_);
  std::string line;
  while (std::getline(in, line)) {
    std::string name = line_name(line);
    if (!name.empty()) names.insert(std::move(name));
  }
  return names;
}

void ResultsFile::put(const std::string& name, const std::string& line, bool replace) const {
  ResultsLock lock(lock_);
  if (!replace) {
    const int fd = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (fd < 0) throw Failure(path_.string() + ": cannot open for appending");
    try {
      write_fully(fd, line + "\n", path_);
      ::fsync(fd);
    } catch (...) {
      ::close(fd);
      throw;
    }
    ::close(fd);
    return;
  }
  std::string kept;
  {
    std::ifstream in(path_);
    std::string old;
    while (std::getline(in, old))
      if (!old.empty() && line_name(old) != name) kept += old + "\n";
  }
  kept += line + "\n";
  const fs::path temp = dir_ / (".results.jsonl.partial-" + std::to_string(::getpid()));
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw Failure(temp.string() + ": cannot write");
  try {
    write_fully(fd, kept, temp);
    ::fsync(fd);
  } catch (...) {
    ::close(fd);
    fs::remove(temp);
    throw;
  }
  ::close(fd);
  std::error_code ec;
  fs::rename(temp, path_, ec);
  if (ec) {
    fs::remove(temp, ec);
    throw Failure(path_.string() + ": cannot replace the results file");
  }
}

// ---- tools -----------------------------------------------------------------

const std::vector<BatchTool>& batch_tools() {
  static const std::vector<BatchTool> tools = {
      {"ism-info", ""}, {"gim-remesh", ".exr"}, {"semireg", ".obj"}, {"torus-remesh", ".obj"}};
  return tools;
}

const BatchTool& batch_tool(const std::string& name) {
  std::string known;
  for (const BatchTool& t : batch_tools()) {
    if (t.name == name) return t;
    known += (known.empty() ? "" : ", ") + t.name;
  }
  throw Failure("ism-batch: unknown tool '" + name + "' (known: " + known + ")");
}

std::string tool_figures(const std::string& report_json) {
  OrderedJson report;
  try {
    report = OrderedJson::parse(report_json);
  } catch (const nlohmann::json::exception&) {
    return "{}";
  }
  OrderedJson figures = OrderedJson::object();
  if (!report.is_object()) return figures.dump();
  if (report.contains("inputs") && report["inputs"].is_array() && !report["inputs"].empty()) {
    const OrderedJson& input = report["inputs"].front();
    if (input.contains("check") && input["check"].is_object()) {
      const OrderedJson& check = input["check"];
      for (const char* key : {"vertices", "faces", "genus", "boundary_loops"})
        if (check.contains(key)) figures["input"][key] = check[key];
    }
  }
  for (const char* section :
       {"base", "map", "image", "grid", "remesh", "distance", "boundary", "meta_mesh"}) {
    if (!report.contains(section) || !report[section].is_object()) continue;
    for (const auto& [key, value] : report[section].items())
      if ((value.is_number() || value.is_boolean()) && key != "seconds")
        figures[section][key] = value;
  }
  return figures.dump();
}

// ---- the batch -------------------------------------------------------------

namespace {

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos;
       at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The last non-empty line of a tool's stderr (progress lines on a terminal
// end with '\r', so both break lines).
std::string last_line(const std::string& text) {
  std::size_t end = text.find_last_not_of("\r\n \t");
  if (end == std::string::npos) return {};
  const std::size_t begin = text.find_last_of("\r\n", end);
  return text.substr(begin == std::string::npos ? 0 : begin + 1,
                     end + 1 - (begin == std::string::npos ? 0 : begin + 1));
}

bool gives_output(const std::vector<std::string>& args) {
  for (const std::string& a : args)
    if (a == "-o" || a == "--output" || a.rfind("--output=", 0) == 0 ||
        (a.rfind("-o", 0) == 0 && a.size() > 2 && a[2] != '-'))
      return true;
  return false;
}

// DIR/.NAME.KIND-: the prefix of a mesh's folder while it is written
// (KIND partial) or replaced (old); the process id follows.
std::string hidden_prefix(const std::string& name, const std::string& kind) {
  std::string s(".");
  s.append(name).append(".").append(kind).append("-");
  return s;
}

std::string hidden_folder(const std::string& name, const std::string& kind) {
  return hidden_prefix(name, kind).append(std::to_string(::getpid()));
}

void remove_stale_folders(const fs::path& out, const std::string& name) {
  // What a killed run of this mesh left.
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(out, ec)) {
    const std::string f = entry.path().filename().string();
    if (f.rfind(hidden_prefix(name, "partial"), 0) == 0 ||
        f.rfind(hidden_prefix(name, "old"), 0) == 0)
      fs::remove_all(entry.path(), ec);
  }
}

// Renames `from` to `to`, moving an existing `to` aside first and removing it after.
void install_folder(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  fs::path old;
  if (fs::exists(to, ec)) {
    old = to.parent_path() / hidden_folder(to.filename().string(), "old");
    fs::rename(to, old, ec);
    if (ec)
      throw Failure(to.string() + ": cannot replace the earlier outputs (" + ec.message() + ")");
  }
  fs::rename(from, to, ec);
  if (ec) throw Failure(to.string() + ": cannot write the outputs (" + ec.message() + ")");
  if (!old.empty()) fs::remove_all(old, ec);
}

}  // namespace

BatchSummary run_batch(const BatchOptions& options,
                       const std::function<void(const std::string&)>& progress) {
  const BatchTool& tool = batch_tool(options.tool);
  if (::access(options.executable.c_str(), X_OK) != 0)
    throw Failure(options.executable.string() + ": " + options.tool +
                  " not found or not executable");
  for (const std::string& a : options.tool_args)
    if (a == "--report" || a.rfind("--report=", 0) == 0)
      throw Failure(
          "ism-batch: the tool options must not give --report (each mesh's report is "
          "DIR/NAME/report.json)");
  const std::vector<BatchEntry> entries = read_batch_list(options.inputs);
  const fs::path out = fs::absolute(options.out).lexically_normal();
  const ResultsFile results(out);
  const std::set<std::string> done = results.names();
  const bool add_output = !tool.output_extension.empty() && !gives_output(options.tool_args);

  std::vector<const BatchEntry*> mine;
  for (std::size_t k = 0; k < entries.size(); ++k)
    if (options.shard.takes(k)) mine.push_back(&entries[k]);

  BatchSummary summary;
  summary.meshes = int(mine.size());
  int position = 0;
  for (const BatchEntry* e : mine) {
    ++position;
    std::ostringstream counter_text;
    counter_text << '[' << position << '/' << mine.size() << "] " << e->name;
    const std::string counter = counter_text.str();
    if (options.skip_existing && done.count(e->name)) {
      ++summary.skipped;
      progress(counter + ": already in " + results.path().string() + ", skipped");
      continue;
    }
    remove_stale_folders(out, e->name);
    const fs::path work = out / hidden_folder(e->name, "partial");
    std::error_code ec;
    fs::create_directory(work, ec);
    if (ec) throw Failure(work.string() + ": cannot create the folder (" + ec.message() + ")");

    std::vector<std::string> argv = {options.executable.string(), e->path.string()};
    if (add_output) argv.insert(argv.end(), {"-o", e->name + tool.output_extension});
    argv.insert(argv.end(), {"--report", "report.json"});
    for (const std::string& a : options.tool_args)
      argv.push_back(
          replace_all(replace_all(a, "{name}", e->name), "{dir}", e->path.parent_path().string()));

    ChildResult r;
    try {
      r = run_child(argv, {.working_dir = work,
                           .stdout_file = work / "stdout.txt",
                           .stderr_file = work / "stderr.txt",
                           .timeout_seconds = options.timeout_seconds});
    } catch (const std::exception& ex) {
      fs::remove_all(work, ec);
      throw Failure(std::string("ism-batch: ") + ex.what());
    }
    if (r.interrupted_by) {
      fs::remove_all(work, ec);
      summary.interrupted_by = r.interrupted_by;
      progress(counter + ": stopped by " + signal_name(r.interrupted_by) + ", no line written");
      return summary;
    }

    OrderedJson line = OrderedJson::object();
    line["name"] = e->name;
    line["input"] = e->path.string();
    line["tool"] = options.tool;
    const std::string report = slurp(work / "report.json");
    std::string error;
    if (r.timed_out) {
      std::ostringstream t;
      t << "timed out after " << options.timeout_seconds << " s";
      error = t.str();
    } else if (r.term_signal) {
      error = "killed by " + signal_name(r.term_signal);
    } else if (r.exit_code != 0) {
      error = last_line(slurp(work / "stderr.txt"));
      if (error.empty())
        error = options.tool + " exited with status " + std::to_string(r.exit_code);
    } else if (report.empty()) {
      error = options.tool + " wrote no report";
    }
    const bool ok = error.empty();
    line["status"] = ok ? "ok" : r.timed_out ? "timeout" : "failed";
    line["error"] = ok ? OrderedJson(nullptr) : OrderedJson(error);
    line["exit_code"] = r.exit_code >= 0 ? OrderedJson(r.exit_code) : OrderedJson(nullptr);
    line["seconds"] = std::round(r.seconds * 1000.0) / 1000.0;
    if (ok) {
      for (const char* f : {"stdout.txt", "stderr.txt"})
        if (fs::exists(work / f) && fs::file_size(work / f) == 0) fs::remove(work / f, ec);
      install_folder(work, out / e->name);
      line["outputs"] = e->name;
      line["figures"] = OrderedJson::parse(tool_figures(report));
      try {
        const auto parsed = nlohmann::json::parse(report);
        if (parsed.contains("peak_memory_mb")) line["peak_memory_mb"] = parsed["peak_memory_mb"];
      } catch (const nlohmann::json::exception&) {
      }
    } else {
      // Outputs of an earlier run would no longer match the mesh's line.
      fs::remove_all(work, ec);
      fs::remove_all(out / e->name, ec);
      line["outputs"] = nullptr;
      line["figures"] = OrderedJson::object();
    }
    line["shard"] = options.shard.str();
    results.put(e->name, line.dump(), done.count(e->name) > 0);

    (ok ? summary.ok : r.timed_out ? summary.timed_out : summary.failed) += 1;
    std::ostringstream message;
    message << counter << ": " << (ok ? "ok" : error) << " (" << std::fixed;
    message.precision(1);
    message << r.seconds << " s)";
    progress(message.str());
  }
  return summary;
}

}  // namespace ism::tool
