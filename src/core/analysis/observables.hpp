#pragma once
// Observables: a function of the current state returning a flat vector of
// doubles with a fixed shape. Accumulators (correlator.hpp) sample them during
// integration without going through Python (doc/analysis.md).
#include "system/System.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace Marble::Observables {

class Observable {
public:
  virtual ~Observable() = default;
  /** Values in C order of shape(). Throws std::out_of_range if a particle is gone. */
  virtual std::vector<double> operator()(System const &system) const = 0;
  virtual std::vector<std::size_t> shape() const = 0;
  virtual std::string name() const = 0;
  std::size_t n_values() const {
    std::size_t n = 1;
    for (auto s : shape())
      n *= s;
    return n;
  }
};

/** Base of the per-particle observables: one row of 3 values per id. */
class PidObservable : public Observable {
public:
  /** Throws std::invalid_argument for an empty list or a negative id,
   * std::out_of_range for an id without a particle in @p system. */
  PidObservable(System const &system, std::vector<int> ids);
  std::vector<int> const &ids() const { return m_ids; }
  std::vector<std::size_t> shape() const override { return {m_ids.size(), 3}; }
  std::vector<double> operator()(System const &system) const override;

protected:
  /** Row of particle at local index @p i. */
  virtual Utils::Vector3d row(System const &system, int i) const = 0;

private:
  std::vector<int> m_ids;
};

/** Unfolded positions (pos + image * box_l). */
class ParticlePositions : public PidObservable {
public:
  using PidObservable::PidObservable;
  std::string name() const override { return "ParticlePositions"; }

protected:
  Utils::Vector3d row(System const &system, int i) const override;
};

class ParticleVelocities : public PidObservable {
public:
  using PidObservable::PidObservable;
  std::string name() const override { return "ParticleVelocities"; }

protected:
  Utils::Vector3d row(System const &system, int i) const override;
};

/** Angular velocities in the lab frame (isotropic spheres: the same as the
 * body frame in this engine). Needs ROTATION (Utils::FeaturesError otherwise). */
class ParticleAngularVelocities : public PidObservable {
public:
  ParticleAngularVelocities(System const &system, std::vector<int> ids);
  std::string name() const override { return "ParticleAngularVelocities"; }

protected:
  Utils::Vector3d row(System const &system, int i) const override;
};

/** Mass-weighted centre-of-mass velocity of the ids, shape (3,). */
class ComVelocity : public Observable {
public:
  ComVelocity(System const &system, std::vector<int> ids);
  std::vector<int> const &ids() const { return m_ids; }
  std::vector<std::size_t> shape() const override { return {3}; }
  std::vector<double> operator()(System const &system) const override;
  std::string name() const override { return "ComVelocity"; }

private:
  std::vector<int> m_ids;
};

} // namespace Marble::Observables
