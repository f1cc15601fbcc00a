#pragma once
// The Khronos glTF validator (npm gltf-validator, installed by
// scripts/install-node-tools.sh) run over .glb files a test wrote.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace ism::test {

inline std::filesystem::path gltf_validator_script() {
  return std::filesystem::path(ISM_SOURCE_DIR) / "scripts" / "gltf-validator" / "validate.mjs";
}

/// Why the validator cannot run here, or nothing when it can.
inline std::optional<std::string> gltf_validator_missing() {
  if (std::system("node --version >/dev/null 2>&1") != 0)
    return "node not found (install Node.js, then scripts/install-node-tools.sh)";
  const auto package = gltf_validator_script().parent_path() / "node_modules" / "gltf-validator";
  if (!std::filesystem::is_directory(package))
    return "gltf-validator not installed at " + package.string() +
           " (run scripts/install-node-tools.sh)";
  return std::nullopt;
}

struct GltfValidation {
  int status = -1;     // 0: no file has an error
  std::string output;  // one JSON line per file: errors, warnings, infos, hints, messages
};

/// Runs the validator over `files` (output captured in `log`).
inline GltfValidation validate_gltf(const std::vector<std::filesystem::path>& files,
                                    const std::filesystem::path& log) {
  std::string command = "node " + gltf_validator_script().string();
  for (const auto& f : files) command += " '" + f.string() + "'";
  command += " >'" + log.string() + "' 2>&1";
  const int raw = std::system(command.c_str());
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, text.str()};
}

}  // namespace ism::test

/// Skips the current test when node or the validator package is missing.
#define ISM_REQUIRE_GLTF_VALIDATOR()                                              \
  do {                                                                            \
    if (const auto why = ::ism::test::gltf_validator_missing())                   \
      GTEST_SKIP() << "glTF validator unavailable, .glb not validated: " << *why; \
  } while (0)

/// Expects every file to pass the validator with no error.
#define ISM_EXPECT_VALID_GLTF(files, log)                                                      \
  do {                                                                                         \
    const auto validation = ::ism::test::validate_gltf(files, log);                            \
    EXPECT_EQ(validation.status, 0) << validation.output;                                      \
    EXPECT_NE(validation.output.find("\"errors\":0"), std::string::npos) << validation.output; \
  } while (0)
