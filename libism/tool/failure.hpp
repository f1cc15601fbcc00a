#pragma once
#include <stdexcept>
#include <string>

namespace ism::tool {

/// A user-facing failure: its message is printed as it is, on one line
/// ("bunny_open.obj: 5 boundary loops, gim-remesh needs a closed surface").
/// Its kind tells a binding which exception to raise (the Python module:
/// ValueError, OSError, RuntimeError).
class Failure : public std::runtime_error {
 public:
  enum class Kind {
    input,     // an input (mesh, features, base) or an option is not what the tool needs
    file,      // a file cannot be read or written: missing, a folder, an input, no space
    internal,  // the computation failed on a valid input
  };
  explicit Failure(const std::string& message, Kind kind = Kind::input)
      : std::runtime_error(message), kind_(kind) {}
  Kind kind() const { return kind_; }

 private:
  Kind kind_;
};

}  // namespace ism::tool
