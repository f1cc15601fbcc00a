#include "mesh/mean_value_weights.hpp"

namespace ism {

CornerWeights mean_value_weights(const std::vector<Triangle>& faces,
                                 const std::function<std::array<Vec3, 3>(int)>& corners) {
  CornerWeights w(faces.size());
  for (std::size_t t = 0; t < faces.size(); ++t) {
    const std::array<Vec3, 3> p = corners(int(t));
    for (int c = 0; c < 3; ++c) {
      const Vec3 a = p[(c + 1) % 3] - p[c], b = p[(c + 2) % 3] - p[c];
      const double la = a.norm(), lb = b.norm();
      // tan(α/2) = |a × b| / (|a||b| + a·b).
      const double tan_half = a.cross(b).norm() / (la * lb + a.dot(b));
      w[t][c] = {tan_half / la, tan_half / lb};
    }
  }
  return w;
}

}  // namespace ism
