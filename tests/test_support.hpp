#pragma once
// Helpers shared by the tests: where the shared models are, and a skip with a
// clear message when ../shared is absent (a user's checkout still passes).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace ism::test {

inline std::filesystem::path shared_dir() {
  return std::filesystem::path(ISM_SHARED_DIR);
}
inline std::filesystem::path shared_models_dir() {
  return shared_dir() / "models";
}
inline bool have_shared_models() {
  return std::filesystem::is_directory(shared_models_dir());
}
inline std::filesystem::path binary_dir() {
  return std::filesystem::path(ISM_BINARY_DIR);
}
/// Regression files of hostile input (tests/data/hostile, README there).
inline std::filesystem::path hostile_dir() {
  return std::filesystem::path(ISM_SOURCE_DIR) / "tests" / "data" / "hostile";
}
/// The fuzzers' seed corpus of one target (fuzz/corpus/TARGET).
inline std::filesystem::path fuzz_corpus_dir(const std::string& target) {
  return std::filesystem::path(ISM_SOURCE_DIR) / "fuzz" / "corpus" / target;
}

}  // namespace ism::test

/// Skips the current test when the shared models are not beside the checkout.
#define ISM_REQUIRE_SHARED_MODELS()                                                     \
  do {                                                                                  \
    if (!::ism::test::have_shared_models())                                             \
      GTEST_SKIP() << "shared models not found at " << ::ism::test::shared_models_dir() \
                   << " (clone ../shared beside the repository to run this test)";      \
  } while (0)
