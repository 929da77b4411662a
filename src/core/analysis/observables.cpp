#include "analysis/observables.hpp"

#include "utils/errors.hpp"

#include <stdexcept>
#include <utility>

namespace Marble::Observables {

namespace {

void check_ids(System const &system, std::vector<int> const &ids) {
  if (ids.empty())
    throw std::invalid_argument("parameter 'ids' must name at least one particle");
  for (int pid : ids) {
    if (pid < 0)
      throw std::invalid_argument("parameter 'ids': particle ids are >= 0, got " +
                                  std::to_string(pid));
    if (!system.particles().exists(pid))
      throw std::out_of_range("parameter 'ids': particle " + std::to_string(pid) +
                              " does not exist");
  }
}

int index_checked(System const &system, int pid) {
  int const i = system.particles().index_of(pid);
  if (i < 0)
    throw std::out_of_range("observable: particle " + std::to_string(pid) +
                            " does not exist (removed after the observable was created?)");
  return i;
}

} // namespace

PidObservable::PidObservable(System const &system, std::vector<int> ids) : m_ids(std::move(ids)) {
  check_ids(system, m_ids);
}

std::vector<int> PidObservable::indices(System const &system) const {
  std::vector<int> idx(m_ids.size());
  for (std::size_t k = 0; k < m_ids.size(); ++k)
    idx[k] = index_checked(system, m_ids[k]);
  return idx;
}

std::vector<double> PidObservable::operator()(System const &system) const {
  auto const idx = indices(system);
  std::vector<double> out(3 * idx.size());
  for (std::size_t k = 0; k < idx.size(); ++k) {
    auto const r = row(system, idx[k]);
    for (int d = 0; d < 3; ++d)
      out[3 * k + d] = r[d];
  }
  return out;
}

Utils::Vector3d ParticlePositions::row(System const &system, int i) const {
  auto const &ps = system.particles();
  return system.box().unfolded(ps.pos[i], ps.image[i]);
}

Utils::Vector3d ParticleVelocities::row(System const &system, int i) const {
  return system.particles().v[i];
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
  Utils::Vector3d p{};
  double m = 0.;
  for (int pid : m_ids) {
    int const i = index_checked(system, pid);
    double const mi = ps.get_mass(i);
    p += mi * ps.v[i];
    m += mi;
  }
  return {p[0] / m, p[1] / m, p[2] / m};
}

} // namespace Marble::Observables
