#pragma once
// Periodic orthorhombic box: lengths, periodicity, minimum image, folding.
#include "box/LeesEdwards.hpp"
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
    if (m_le.active()) {
      // Lees-Edwards: the image k box lengths up along the normal is
      // displaced by k * offset along the shear direction
      int const n = m_le.shear_plane_normal, s = m_le.shear_direction;
      double const k = std::round(d[n] / m_length[n]);
      d[n] -= k * m_length[n];
      d[s] -= k * le_offset_wrapped();
      for (int i = 0; i < 3; ++i)
        if (i != n && m_periodic[i])
          d[i] -= m_length[i] * std::round(d[i] / m_length[i]);
      return d;
    }
    for (int i = 0; i < 3; ++i)
      if (m_periodic[i])
        d[i] -= m_length[i] * std::round(d[i] / m_length[i]);
    return d;
  }

  /** Lees-Edwards state (inactive by default; System keeps it current). */
  LeesEdwardsBC const &lees_edwards() const { return m_le; }
  void set_lees_edwards(LeesEdwardsBC const &le) { m_le = le; }
  /** The Lees-Edwards offset wrapped into [0, L_s). */
  double le_offset_wrapped() const {
    double const L = m_length[m_le.shear_direction];
    double const o = m_le.pos_offset - L * std::floor(m_le.pos_offset / L);
    return o < L ? o : 0.;
  }

  /** Fold @p pos into [0, L) along periodic axes, counting the images.
   * With Lees-Edwards the normal is folded first and each crossing of the
   * shear plane shifts pos along the shear direction by -offset; returns the
   * net number of upward crossings k (0 without Lees-Edwards): the caller
   * shifts the velocity by -k * shear_velocity. */
  int fold(Utils::Vector3d &pos, Utils::Vector3i &image) const {
    if (m_le.active()) {
      int const n = m_le.shear_plane_normal, s = m_le.shear_direction;
      int const k = fold_axis(pos, image, n);
      if (k != 0)
        pos[s] -= k * le_offset_wrapped();
      for (int i = 0; i < 3; ++i)
        if (i != n && m_periodic[i])
          fold_axis(pos, image, i);
      return k;
    }
    for (int i = 0; i < 3; ++i) {
      if (!m_periodic[i])
        continue;
      fold_axis(pos, image, i);
    }
    return 0;
  }

  Utils::Vector3d unfolded(Utils::Vector3d const &pos, Utils::Vector3i const &image) const {
    return {pos[0] + image[0] * m_length[0], pos[1] + image[1] * m_length[1],
            pos[2] + image[2] * m_length[2]};
  }

private:
  /** Fold axis @p i; returns the number of box lengths subtracted. */
  int fold_axis(Utils::Vector3d &pos, Utils::Vector3i &image, int i) const {
    int k = 0;
    double const n = std::floor(pos[i] / m_length[i]);
    if (n != 0.) {
      pos[i] -= n * m_length[i];
      image[i] += static_cast<int>(n);
      k = static_cast<int>(n);
    }
    // Round-off can leave pos == L; put it on the lower face.
    if (pos[i] >= m_length[i]) {
      pos[i] -= m_length[i];
      image[i] += 1;
      k += 1;
    } else if (pos[i] < 0.) {
      pos[i] = 0.;
    }
    return k;
  }

  LeesEdwardsBC m_le;
  Utils::Vector3d m_length{1., 1., 1.};
  std::array<bool, 3> m_periodic{true, true, true};
};

} // namespace Marble
