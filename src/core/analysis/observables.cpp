#include "analysis/observables.hpp"

#include "utils/errors.hpp"

#include <stdexcept>
#include <utility>

namespace Marble::Observables {

namespace {

void check_ids(System const &system, std::vector<int> const &ids) {
  if (ids.empty())
    throw std::invalid_argument("parameter 'ids' must name at least one particle");
  for (int pid : ids)
    if (pid < 0)
      throw std::invalid_argument("parameter 'ids': particle ids are >= 0, got " +
                                  std::to_string(pid));
  if (auto const missing = system.first_missing_particle(ids))
    throw std::out_of_range("parameter 'ids': particle " + std::to_string(*missing) +
                            " does not exist");
}

} // namespace

PidObservable::PidObservable(System const &system, std::vector<int> ids) : m_ids(std::move(ids)) {
  check_ids(system, m_ids);
}

// Each rank fills the rows of its particles (zeros elsewhere), then a sum
// over the ranks; the extra last entries count where each id was found.
std::vector<double> PidObservable::operator()(System const &system) const {
  std::size_t const n = m_ids.size();
  std::vector<double> out(4 * n, 0.);
  for (std::size_t k = 0; k < n; ++k) {
    int const i = system.particles().index_of(m_ids[k]);
    if (i < 0)
      continue;
    auto const r = row(system, i);
    for (int d = 0; d < 3; ++d)
      out[3 * k + d] = r[d];
    out[3 * n + k] = 1.;
  }
  system.comm().sum_inplace(out.data(), static_cast<int>(out.size()));
  for (std::size_t k = 0; k < n; ++k)
    if (out[3 * n + k] != 1.)
      throw std::out_of_range("observable: particle " + std::to_string(m_ids[k]) +
                              " does not exist (removed after the observable was created?)");
  out.resize(3 * n);
  return out;
}

Utils::Vector3d ParticlePositions::row(System const &system, int i) const {
  auto const &ps = system.particles();
  return system.box().unfolded(ps.pos[i], ps.image[i]);
}

Utils::Vector3d ParticleVelocities::row(System const &system, int i) const {
  return system.folded_velocity(i); // Lees-Edwards: frame of the folded position
}

ParticleAngularVelocities::ParticleAngularVelocities(System const &system, std::vector<int> ids)
    : PidObservable(system, std::move(ids)) {
#ifndef ROTATION
  throw Utils::FeaturesError("ROTATION", "ParticleAngularVelocities");
#endif
}

Utils::Vector3d ParticleAngularVelocities::row(System const &system, int i) const {
#ifdef ROTATION
  return system.particles().omega[i];
#else
  (void)system, (void)i;
  return {};
#endif
}

ComVelocity::ComVelocity(System const &system, std::vector<int> ids) : m_ids(std::move(ids)) {
  check_ids(system, m_ids);
}

std::vector<double> ComVelocity::operator()(System const &system) const {
  auto const &ps = system.particles();
  double acc[5] = {0., 0., 0., 0., 0.}; // p, m, number found
  for (int pid : m_ids) {
    int const i = ps.index_of(pid);
    if (i < 0)
      continue;
    double const mi = ps.get_mass(i);
    for (int d = 0; d < 3; ++d)
      acc[d] += mi * ps.v[i][d];
    acc[3] += mi;
    acc[4] += 1.;
  }
  system.comm().sum_inplace(acc, 5);
  if (acc[4] != static_cast<double>(m_ids.size()))
    throw std::out_of_range("observable: a particle of ComVelocity does not exist (removed "
                            "after the observable was created?)");
  return {acc[0] / acc[3], acc[1] / acc[3], acc[2] / acc[3]};
}

} // namespace Marble::Observables
