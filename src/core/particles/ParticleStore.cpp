#include "particles/ParticleStore.hpp"

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cstring>
#include <type_traits>

namespace Marble {

// Visit every array that holds a value for locals and ghosts.
template <typename F> void ParticleStore::for_each_array(F &&fn) {
  fn(id);
  fn(type);
  fn(pos);
  fn(v);
  fn(f);
#ifdef MASS
  fn(mass);
#endif
#ifdef ROTATION
  fn(omega);
  fn(torque);
  fn(rinertia);
  fn(rotation);
#endif
}

// Visit every array that holds a value for locals only.
template <typename F> void ParticleStore::for_each_local_array(F &&fn) {
  fn(image);
  fn(pos_at_rebuild);
#ifdef EXTERNAL_FORCE
  fn(ext_force);
  fn(ext_torque);
  fn(fix);
#endif
  fn(gamma);
  fn(gamma_rot);
}

std::vector<int> ParticleStore::ids_sorted() const {
  std::vector<int> out(id.begin(), id.begin() + m_n_local);
  std::sort(out.begin(), out.end());
  return out;
}

void ParticleStore::add(ParticleProperties const &p) {
  assert(n_ghost() == 0);
  assert(p.id >= 0 && !exists(p.id));
  id.push_back(p.id);
  type.push_back(p.type);
  pos.push_back(p.pos);
  v.push_back(p.v);
  f.push_back({});
#ifdef MASS
  mass.push_back(p.mass);
#endif
#ifdef ROTATION
  omega.push_back(p.omega);
  torque.push_back({});
  rinertia.push_back(p.rinertia);
  rotation.push_back(p.rotation ? 1 : 0);
#endif
  image.push_back(p.image);
  pos_at_rebuild.push_back(p.pos);
#ifdef EXTERNAL_FORCE
  ext_force.push_back(p.ext_force);
  ext_torque.push_back(p.ext_torque);
  fix.push_back(p.fix);
#endif
  gamma.push_back(p.gamma);
  gamma_rot.push_back(p.gamma_rot);
  if (p.id >= static_cast<int>(m_index.size()))
    m_index.resize(p.id + 1, -1);
  m_index[p.id] = m_n_local++;
}

ParticleProperties ParticleStore::get(int pid) const {
  int const i = index_of(pid);
  assert(i >= 0);
  ParticleProperties p;
  p.id = id[i];
  p.type = type[i];
  p.pos = pos[i];
  p.v = v[i];
  p.image = image[i];
  p.mass = get_mass(i);
#ifdef ROTATION
  p.rotation = rotation[i] != 0;
  p.rinertia = rinertia[i];
  p.omega = omega[i];
#endif
#ifdef EXTERNAL_FORCE
  p.ext_force = ext_force[i];
  p.ext_torque = ext_torque[i];
  p.fix = fix[i];
#endif
  p.gamma = gamma[i];
  p.gamma_rot = gamma_rot[i];
  return p;
}

void ParticleStore::remove(int pid) {
  assert(n_ghost() == 0);
  int const i = index_of(pid);
  assert(i >= 0);
  int const last = m_n_local - 1;
  // Move the last particle into the hole.
  auto move_last = [&](auto &arr) {
    arr[i] = arr[last];
    arr.pop_back();
  };
  for_each_array(move_last);
  for_each_local_array(move_last);
  m_index[pid] = -1;
  --m_n_local;
  if (i < m_n_local)
    m_index[id[i]] = i;
  while (!m_index.empty() && m_index.back() < 0)
    m_index.pop_back();
}

void ParticleStore::clear() {
  for_each_array([](auto &arr) { arr.clear(); });
  for_each_local_array([](auto &arr) { arr.clear(); });
  ghost_owner.clear();
  ghost_shift.clear();
  m_index.clear();
  m_n_local = 0;
}

void ParticleStore::clear_ghosts() {
  for_each_array([this](auto &arr) { arr.resize(m_n_local); });
  ghost_owner.clear();
  ghost_shift.clear();
}

void ParticleStore::add_ghost(int owner, Utils::Vector3d const &shift) {
  append_ghost(ghost_record(owner, shift), owner, shift);
}

void ParticleStore::add_remote_ghost(GhostRecord const &r, int marker) {
  append_ghost(r, marker, Utils::Vector3d{});
}

void ParticleStore::append_ghost(GhostRecord const &r, int owner, Utils::Vector3d const &shift) {
  id.push_back(r.id);
  type.push_back(r.type);
  pos.push_back(r.pos);
  v.push_back(r.v);
  f.push_back({});
#ifdef MASS
  mass.push_back(r.mass);
#endif
#ifdef ROTATION
  omega.push_back(r.omega);
  torque.push_back({});
  rinertia.push_back(r.rinertia);
  rotation.push_back(r.rotation);
#endif
  ghost_owner.push_back(owner);
  ghost_shift.push_back(shift);
}

GhostRecord ParticleStore::ghost_record(int i, Utils::Vector3d const &shift) const {
  GhostRecord r;
  r.id = id[i];
  r.type = type[i];
  r.pos = pos[i] + shift;
  r.v = v[i];
  r.mass = get_mass(i);
#ifdef ROTATION
  r.omega = omega[i];
  r.rinertia = rinertia[i];
  r.rotation = rotation[i];
#endif
  return r;
}

void ParticleStore::permute_locals(std::vector<int> const &order, bool skip_pos_at_rebuild) {
  assert(n_ghost() == 0 && static_cast<int>(order.size()) == m_n_local);
  std::size_t const n = order.size();
  int const *const o = order.data();
  auto apply = [&](auto &arr) {
    using T = typename std::decay_t<decltype(arr)>::value_type;
    static_assert(std::is_trivially_copyable_v<T>);
    // an array whose elements are all the same bytes (masses of 1, zero
    // torques, default frictions, ...) is its own permutation: one compare
    // of each element with the next instead of a gather and a write
    if (n < 2 || std::memcmp(arr.data(), arr.data() + 1, (n - 1) * sizeof(T)) == 0)
      return;
    auto &tmp = std::get<std::vector<T>>(m_permute_spare);
    tmp.resize(n);
    T const *const src = arr.data();
    T *const dst = tmp.data();
    for (std::size_t k = 0; k < n; ++k)
      dst[k] = src[static_cast<std::size_t>(o[k])];
    arr.swap(tmp);
  };
  for_each_array(apply);
  for_each_local_array([&](auto &arr) {
    if (!(skip_pos_at_rebuild && static_cast<void *>(&arr) == static_cast<void *>(&pos_at_rebuild)))
      apply(arr);
  });
  for (int k = 0; k < m_n_local; ++k)
    m_index[id[k]] = k;
}

} // namespace Marble
