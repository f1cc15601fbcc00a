#pragma once
// One number per edge of a mesh, for hash maps and sorted lists of edges:
// the two vertex indices (non-negative, below 2^32) packed into 64 bits.
#include <algorithm>
#include <cstdint>

namespace ism {

/// The directed edge a -> b (a in the high half: keys sort by a, then b).
inline std::uint64_t directed_edge_key(int a, int b) {
  return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
}

/// The undirected edge {a, b}: directed_edge_key(min, max).
inline std::uint64_t undirected_edge_key(int a, int b) {
  return directed_edge_key(std::min(a, b), std::max(a, b));
}

}  // namespace ism
