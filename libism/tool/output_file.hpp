#pragma once
// An output that appears only when complete: writers write temp_path(), a
// name in the target's folder with the same extension; commit() renames it
// over the target; destruction without commit removes it.
#include <filesystem>
#include <vector>

namespace ism::tool {

class OutputFile {
 public:
  /// Throws Failure if the target is one of the inputs or its folder is missing.
  OutputFile(std::filesystem::path target, const std::vector<std::filesystem::path>& inputs);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  const std::filesystem::path& temp_path() const { return temp_; }
  const std::filesystem::path& target() const { return target_; }
  void commit();

 private:
  std::filesystem::path target_, temp_;
  bool committed_ = false;
};

/// True when both paths name the same file (existing or not).
bool same_file(const std::filesystem::path& a, const std::filesystem::path& b);

}  // namespace ism::tool
