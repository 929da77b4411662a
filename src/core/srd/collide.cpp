// SRD collision step (reference.md section 6; Malevanets & Kapral 1999;
// Andersen variant: Allahyari & Gompper / Noguchi et al.; the cell thermostat
// draws the relative kinetic energy of a cell from its Gamma distribution).
#include "srd/Fluid.hpp"
#include "srd/random.hpp"

#include "box/BoxGeometry.hpp"

#include <cmath>

namespace Marble::Srd {

using Utils::Vector3d;

namespace {
Vector3d cross(Vector3d const &a, Vector3d const &b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// Rodrigues: rotate w by angle (cos c, sin s) about the unit axis n.
Vector3d rotate(Vector3d const &w, Vector3d const &n, double c, double s) {
  return c * w + s * cross(n, w) + ((1. - c) * (n * w)) * n;
}

// Solve the symmetric 3x3 system A x = b (Cramer); false if singular.
bool solve3(double const A[3][3], Vector3d const &b, Vector3d &x) {
  double const det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
                     A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
                     A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
  double const scale = A[0][0] + A[1][1] + A[2][2];
  if (!(std::abs(det) > 1e-12 * scale * scale * scale))
    return false;
  for (int k = 0; k < 3; ++k) {
    double M[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        M[i][j] = (j == k) ? b[i] : A[i][j];
    x[k] = (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
            M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
            M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) /
           det;
  }
  return true;
}
} // namespace

void Fluid::collide(BoxGeometry const &box) {
  auto const &L = box.length();
  double const a0 = m_p.cell_size;
  std::uint64_t const c = m_n_collisions;
  Vector3d shift{};
  if (m_p.shift) // uniform in (-a0/2, a0/2]^3, keyed by (seed, collision)
    shift = a0 * Utils::noise_uniform(m_p.seed, Utils::RNGSalt::srd_shift, c, 0, 0);
  int const n = size();
  // along a wall axis the cells are not wrapped (k + 1 in [0, n + 1]): no
  // cell holds particles from both sides of a wall
  Utils::Vector3i gdim = m_grid;
  if (m_p.wall_axis >= 0)
    gdim[m_p.wall_axis] += 2;
  int const n_cells = gdim[0] * gdim[1] * gdim[2];
  // counting sort of the particles into the shifted cells
  m_cell.resize(n);
  m_count.assign(n_cells + 1, 0);
  double const inv_a0 = 1. / a0;
  for (int i = 0; i < n; ++i) {
    int g = 0;
    for (int d = 0; d < 3; ++d) {
      // pos in [0, L), shift in (-a0/2, a0/2]: k in [-1, n_d]
      int k = static_cast<int>(std::floor((pos[i][d] - shift[d]) * inv_a0));
      if (d == m_p.wall_axis)
        k += 1;
      else
        k = k < 0 ? k + m_grid[d] : (k >= m_grid[d] ? k - m_grid[d] : k);
      g = g * gdim[d] + k;
    }
    m_cell[i] = g;
    ++m_count[g + 1];
  }
  for (int g = 0; g < n_cells; ++g)
    m_count[g + 1] += m_count[g];
  m_order.resize(n);
  m_start.assign(m_count.begin(), m_count.end());
  for (int i = 0; i < n; ++i)
    m_order[m_start[m_cell[i]]++] = i;
  // permute the arrays into cell order (contiguous cells; streaming stays sequential)
  m_p2.resize(n), m_v2.resize(n), m_id2.resize(n), m_t2.resize(n);
  for (int k = 0; k < n; ++k) {
    int const i = m_order[k];
    m_p2[k] = pos[i], m_v2[k] = v[i], m_id2[k] = id[i], m_t2[k] = type[i];
  }
  pos.swap(m_p2), v.swap(m_v2), id.swap(m_id2), type.swap(m_t2);
  double const ca = std::cos(m_p.angle), sa = std::sin(m_p.angle);
  double const sig = std::sqrt(m_p.kT / m_p.mass);
  std::vector<Vector3d> xi;
  for (int g = 0; g < n_cells; ++g) {
    int const b = m_count[g], e = m_count[g + 1], nc = e - b;
    if (nc < 2)
      continue; // one particle: nothing to exchange
    Vector3d u{};
    for (int i = b; i < e; ++i)
      u += v[i];
    u *= 1. / static_cast<double>(nc);
    if (m_p.rule == CollisionRule::srd) {
      Vector3d const axis = random_axis(m_p.seed, c, static_cast<std::uint64_t>(g));
      for (int i = b; i < e; ++i)
        v[i] = u + rotate(v[i] - u, axis, ca, sa);
    } else { // Andersen: new relative velocities from the Maxwellian
      xi.resize(nc);
      Vector3d xm{};
      for (int k = 0; k < nc; ++k) {
        auto const r = gauss4(m_p.seed, Utils::RNGSalt::srd_at, c,
                              static_cast<std::uint64_t>(id[b + k]), 0);
        xi[k] = sig * Vector3d{r[0], r[1], r[2]};
        xm += xi[k];
      }
      xm *= 1. / static_cast<double>(nc);
      Vector3d omega{};
      Vector3d rc{};
      if (m_p.conserve_angular) {
        // AT+a: restore the cell's angular momentum about its centre of mass
        // (positions relative to the shifted cell's corner, no periodic jump)
        std::vector<Vector3d> r(nc);
        for (int k = 0; k < nc; ++k) {
          for (int d = 0; d < 3; ++d) {
            double const y = pos[b + k][d] - shift[d];
            r[k][d] = y - a0 * std::floor(y / a0);
          }
          rc += r[k];
        }
        rc *= 1. / static_cast<double>(nc);
        double I[3][3] = {};
        Vector3d dL{};
        for (int k = 0; k < nc; ++k) {
          Vector3d const q = r[k] - rc;
          double const q2 = q.norm2();
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
              I[i][j] += (i == j ? q2 : 0.) - q[i] * q[j];
          dL += cross(q, v[b + k] - u - (xi[k] - xm));
        }
        bool ok = solve3(I, dL, omega);
        if (!ok && nc == 2) { // collinear pair: I = 2(q^2 - q q), dL is normal to q
          double const tr = I[0][0] + I[1][1] + I[2][2];
          ok = tr > 0.;
          omega = (tr > 0. ? 2. / tr : 0.) * dL;
        }
        if (ok)
          for (int k = 0; k < nc; ++k)
            xi[k] += cross(omega, r[k] - rc);
      }
      for (int k = 0; k < nc; ++k)
        v[b + k] = u + xi[k] - xm;
      continue;
    }
    if (m_p.thermostat) {
      // scale relative velocities so the cell's relative kinetic energy is a
      // draw from its equilibrium Gamma(3(nc-1)/2, kT) distribution
      double e_now = 0.;
      for (int i = b; i < e; ++i)
        e_now += (v[i] - u).norm2();
      e_now *= 0.5 * m_p.mass;
      int const dof = 3 * (nc - 1);
      double e_new = 0.;
      for (int k = 0; k < dof; k += 4) {
        auto const r = gauss4(m_p.seed, Utils::RNGSalt::srd_thermo, c, static_cast<std::uint64_t>(g),
                              static_cast<std::uint64_t>(k / 4));
        for (int j = 0; j < 4 && k + j < dof; ++j)
          e_new += r[j] * r[j];
      }
      e_new *= 0.5 * m_p.kT;
      if (e_now > 0.) {
        double const f = std::sqrt(e_new / e_now);
        for (int i = b; i < e; ++i)
          v[i] = u + f * (v[i] - u);
      }
    }
  }
  (void)L;
  ++m_n_collisions;
}

} // namespace Marble::Srd
