#include "constraints/Constraints.hpp"

#include "utils/errors.hpp"
#include "utils/noise.hpp"

#include <algorithm>
#include <cmath>

namespace Marble {

using Utils::Vector3d;

int Constraints::add_wall(Wall w) {
  w.id = m_next_id++;
  m_walls.push_back(w);
  return w.id;
}

void Constraints::remove(int id) {
  m_walls.erase(std::remove_if(m_walls.begin(), m_walls.end(), [id](Wall const &w) { return w.id == id; }),
                m_walls.end());
}

Wall const *Constraints::find(int id) const {
  for (auto const &w : m_walls)
    if (w.id == id)
      return &w;
  return nullptr;
}

std::vector<char> Constraints::wall_types(int n_types) const {
  std::vector<char> out(n_types, 0);
  for (auto const &w : m_walls)
    if (w.type < n_types)
      out[w.type] = 1;
  return out;
}

namespace {
// Folded position (periodic axes) for the distance to the wall plane.
Vector3d folded(BoxGeometry const &box, Vector3d p) {
  Utils::Vector3i img{};
  box.fold(p, img);
  return p;
}
} // namespace

void Constraints::add_forces(ParticleStore &ps, BoxGeometry const &box, InteractionTable const &ia,
                             NoiseContext const &noise, std::uint64_t step) {
  int const nt = ia.n_types();
  for (auto &w : m_walls) {
    w.total_force = {};
    w.energy = 0.;
    if (w.type >= nt)
      continue;
    for (int i = 0; i < ps.n_local(); ++i) {
      int const t = ps.type[i];
      IAParams const &p = ia.get(w.type, t);
      TunableSlipParams const &ts = p.get<TunableSlip>();
      double const range = std::max(p.max_cut, TunableSlip::range(ts));
      if (range <= 0.)
        continue;
      double const z = w.normal * folded(box, ps.pos[i]) - w.dist;
      if (z >= range)
        continue;
      bool const repulsive = any_conservative(p);
      if (z <= 0. && !repulsive)
        continue; // behind a friction-only wall: outside its fluid, no force
      if (z <= 0.)
        throw Utils::RuntimeError(
            "particle " + std::to_string(ps.id[i]) + " penetrated wall " + std::to_string(w.id) +
            " (distance " + Utils::to_str(z) + ") at step " + std::to_string(step) +
            ": likely cause: time step too large for the wall repulsion, or the particle "
            "was placed behind the wall");
      Vector3d f = (conservative_pair(p, z).force_over_r * z) * w.normal;
#ifdef TUNABLE_SLIP
      double const zl = z - ts.offset; // depth into the friction layer
      if (ts.active && noise.on && zl < ts.r_cut) {
        double const wz = zl <= 0. ? 1. : 1. - zl / ts.r_cut;
        Vector3d const xi = Utils::noise_uniform(noise.seed, TunableSlip::salt,
                                                 noise.counter, static_cast<std::uint64_t>(ps.id[i]),
                                                 static_cast<std::uint64_t>(w.id));
        f += (-ts.gamma * wz) * (ps.v[i] - w.velocity) + (ts.pref_noise * std::sqrt(wz)) * xi;
      }
#else
      (void)noise;
#endif
      ps.f[i] += f;
      w.total_force -= f;
    }
  }
}

double Constraints::energy(ParticleStore const &ps, BoxGeometry const &box, InteractionTable const &ia) const {
  double e = 0.;
  int const nt = ia.n_types();
  for (auto const &w : m_walls) {
    if (w.type >= nt)
      continue;
    for (int i = 0; i < ps.n_local(); ++i) {
      IAParams const &p = ia.get(w.type, ps.type[i]);
      if (p.max_cut <= 0.)
        continue;
      double const z = w.normal * folded(box, ps.pos[i]) - w.dist;
      if (z >= p.max_cut || z <= 0.)
        continue;
      e += conservative_pair(p, z).energy;
    }
  }
  return e;
}

} // namespace Marble
