#pragma once
#include <stdexcept>

namespace ism::tool {

/// A user-facing failure: its message is printed as it is, on one line
/// ("bunny_open.obj: 5 boundary loops, gim-remesh needs a closed surface").
class Failure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace ism::tool
