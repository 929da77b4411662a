#pragma once
// Periodic orthorhombic box: lengths, periodicity, minimum image, folding.
#include "utils/Vector.hpp"

#include <array>
#include <cmath>

namespace Marble {

class BoxGeometry {
public:
  Utils::Vector3d const &length() const { return m_length; }
  /** Lengths must be finite and > 0 (checked by the caller: System). */
  void set_length(Utils::Vector3d const &l) { m_length = l; }
  bool periodic(int d) const { return m_periodic[d]; }
  void set_periodic(int d, bool p) { m_periodic[d] = p; }
  double volume() const { return m_length[0] * m_length[1] * m_length[2]; }

  /** Minimum-image vector a - b (only along periodic axes). */
  Utils::Vector3d get_mi_vector(Utils::Vector3d const &a, Utils::Vector3d const &b) const {
    Utils::Vector3d d = a - b;
    for (int i = 0; i < 3; ++i)
      if (m_periodic[i])
        d[i] -= m_length[i] * std::round(d[i] / m_length[i]);
    return d;
  }

  /** Fold @p pos into [0, L) along periodic axes, counting the images. */
  void fold(Utils::Vector3d &pos, Utils::Vector3i &image) const {
    for (int i = 0; i < 3; ++i) {
      if (!m_periodic[i])
        continue;
      double const n = std::floor(pos[i] / m_length[i]);
      if (n != 0.) {
        pos[i] -= n * m_length[i];
        image[i] += static_cast<int>(n);
      }
      // Round-off can leave pos == L; put it on the lower face.
      if (pos[i] >= m_length[i]) {
        pos[i] -= m_length[i];
        image[i] += 1;
      } else if (pos[i] < 0.) {
        pos[i] = 0.;
      }
    }
  }

  Utils::Vector3d unfolded(Utils::Vector3d const &pos, Utils::Vector3i const &image) const {
    return {pos[0] + image[0] * m_length[0], pos[1] + image[1] * m_length[1],
            pos[2] + image[2] * m_length[2]};
  }

private:
  Utils::Vector3d m_length{1., 1., 1.};
  std::array<bool, 3> m_periodic{true, true, true};
};

} // namespace Marble
