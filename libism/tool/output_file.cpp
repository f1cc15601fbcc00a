#include "tool/output_file.hpp"

#include "tool/failure.hpp"

#include <unistd.h>

namespace ism::tool {

namespace fs = std::filesystem;

bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}

OutputFile::OutputFile(fs::path target, const std::vector<fs::path>& inputs)
    : target_(std::move(target)) {
  for (const fs::path& input : inputs)
    if (same_file(target_, input))
      throw Failure(target_.string() + ": refusing to overwrite an input file",
                    Failure::Kind::file);
  fs::path folder = target_.parent_path();
  std::error_code ec;
  if (!folder.empty() && !fs::is_directory(folder, ec))
    throw Failure(target_.string() + ": output folder " + folder.string() + " does not exist",
                  Failure::Kind::file);
  if (fs::is_directory(target_, ec))
    throw Failure(target_.string() + ": is a folder", Failure::Kind::file);
  // Same folder (so the rename is atomic) and same extension (writers pick
  // the format from it).
  temp_ = folder / ("." + target_.stem().string() + ".partial-" + std::to_string(::getpid()) +
                    target_.extension().string());
}

OutputFile::~OutputFile() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(temp_, ec);
  }
}

void OutputFile::commit() {
  std::error_code ec;
  fs::rename(temp_, target_, ec);
  if (ec)
    throw Failure(target_.string() + ": cannot write the file (" + ec.message() + ")",
                  Failure::Kind::file);
  committed_ = true;
}

}  // namespace ism::tool
