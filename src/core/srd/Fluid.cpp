// SRD streaming and the colloid boundary rules (seed 003, section 3).
#include "srd/Fluid.hpp"
#include "srd/random.hpp"

#include "system/System.hpp"
#include "utils/errors.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace Marble::Srd {

using Utils::Vector3d;

namespace {
Vector3d cross(Vector3d const &a, Vector3d const &b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
void fold(Vector3d &x, Vector3d const &L) {
  for (int d = 0; d < 3; ++d) {
    if (x[d] < 0. || x[d] >= L[d]) [[unlikely]] {
      x[d] -= L[d] * std::floor(x[d] / L[d]);
      if (x[d] >= L[d]) // rounding of a tiny negative x
        x[d] = 0.;
    }
  }
}

// The colloids an SRD fluid sees: MD particles of a type with an active
// boundary for some SRD type, gathered from every rank (sorted by id): an
// SRD particle may meet a colloid owned by another rank; the momentum handed
// to a colloid is summed over the ranks and applied by its owner.
struct ColloidRef {
  int index; // local index on the owning rank, -1 on the others
  int rank, id, type;
  Vector3d R, V, W;
  double M, I;
};
static_assert(std::is_trivially_copyable_v<ColloidRef>);
// An SRD particle found inside colloid j (index into the colloid list) after
// streaming: its position relative to the centre and its velocity.
struct Hit {
  int pid, j, rank, index, type;
  Vector3d d, v;
};
static_assert(std::is_trivially_copyable_v<Hit>);
// Rule `rough`: the fraction of the relative tangential velocity kept, 1 - 2K
// with K = chi/(1 + chi), chi = 2/5 (a uniform sphere).
constexpr double kRoughKeep = 1. - 2. * (0.4 / 1.4);
// Minimum image of a - b for positions folded into [0, L): one conditional
// wrap per axis (the general rounding only for a pair not folded).
Vector3d mi_folded(Vector3d const &a, Vector3d const &b, Vector3d const &L) {
  Vector3d d = a - b;
  for (int k = 0; k < 3; ++k) {
    double const h = 0.5 * L[k];
    double x = d[k];
    x = x > h ? x - L[k] : (x < -h ? x + L[k] : x);
    if (!(std::abs(x) <= h)) [[unlikely]]
      x -= L[k] * std::round(x / L[k]);
    d[k] = x;
  }
  return d;
}
// A particle inside by no more than round-off (an event bounce at the end of
// a step leaves it on the surface) is not "inside".
bool deep_inside(double d2, double r) { return d2 < r * r * (1. - 1e-12); }
} // namespace

void Fluid::check_geometry(BoxGeometry const &box, double dt) {
  auto const &L = box.length();
  double const a0 = m_p.cell_size;
  for (int d = 0; d < 3; ++d) {
    if (!box.periodic(d))
      throw std::invalid_argument("SRD needs a box periodic in all three directions");
    double const n = L[d] / a0;
    if (std::abs(n - std::round(n)) > 1e-9 * n || std::round(n) < 1.)
      throw std::invalid_argument("parameter 'cell_size' (" + Utils::to_str(a0) +
                                  ") must divide the box length " + Utils::to_str(L[d]) +
                                  " along axis " + std::to_string(d));
    m_grid[d] = static_cast<int>(std::round(n));
  }
  if (m_p.wall_axis >= 0 && !(wall_hi(L[m_p.wall_axis]) <= L[m_p.wall_axis]))
    throw std::invalid_argument("parameter 'wall_positions': the upper wall (" + Utils::to_str(m_p.wall_hi) +
                                ") must lie inside the box (length " + Utils::to_str(L[m_p.wall_axis]) +
                                " along axis " + std::to_string(m_p.wall_axis) + ")");
  if (dt > 0.) {
    double const k = m_p.tau / dt;
    if (std::abs(k - std::round(k)) > 1e-9 * k || std::round(k) < 1.)
      throw std::invalid_argument("parameter 'tau' (" + Utils::to_str(m_p.tau) +
                                  ") must be a positive integer multiple of time_step (" +
                                  Utils::to_str(dt) + ")");
    m_n_tau = static_cast<int>(std::round(k));
  }
}

bool Fluid::is_srd_type(int t) const {
  for (int x : type)
    if (x == t)
      return true;
  return false;
}

BoundaryParams Fluid::boundary(int c, int s) const {
  if (!m_ia || c >= m_ia->n_types() || s >= m_ia->n_types())
    return {};
  return m_ia->get(c, s).get<SRDBoundary>();
}

bool Fluid::any_boundary() const { return m_ia && m_ia->any_active<SRDBoundary>(); }

namespace {
// Collective (the interaction table, hence any_boundary(), is the same on every rank).
std::vector<ColloidRef> colloids_of(System const &s, Fluid const &f) {
  std::vector<ColloidRef> out;
  if (!f.any_boundary())
    return out;
  auto const &ps = s.particles();
  int const me = s.comm().rank();
  // the types with a boundary for some SRD type
  int const nt = std::min(Fluid::max_type, s.interactions().n_types());
  std::vector<char> is_colloid(static_cast<std::size_t>(nt), 0);
  for (int c = 0; c < nt; ++c)
    for (int t = 0; t < nt && !is_colloid[c]; ++t)
      is_colloid[c] = f.boundary(c, t).active;
  for (int i = 0; i < ps.n_local(); ++i) {
    if (ps.type[i] < 0 || ps.type[i] >= nt || !is_colloid[ps.type[i]])
      continue;
    ColloidRef c{i, me, ps.id[i], ps.type[i], ps.pos[i], ps.v[i], {}, ps.get_mass(i), 0.};
#ifdef ROTATION
    c.W = ps.omega[i];
    c.I = ps.rotation[i] ? ps.rinertia[i] : 0.;
#endif
    out.push_back(c);
  }
  if (s.comm().parallel()) {
    out = s.comm().allgatherv(out);
    for (auto &c : out)
      if (c.rank != me)
        c.index = -1;
  }
  std::sort(out.begin(), out.end(), [](ColloidRef const &a, ColloidRef const &b) { return a.id < b.id; });
  return out;
}
} // namespace

void Fluid::near(Vector3d R, double r, Vector3d const &L, std::vector<int> &out) const {
  // a particle now within r of R sat, at the last collision's sort, in a
  // cell within r + m_disp of R (cells of this rank's local grid, collide.cpp):
  // the cells whose box comes that close (a sphere of cells, not the cube)
  fold(R, L);
  double const rr = r + m_disp + 1e-9 * L[0];
  double const a0 = m_p.cell_size, inv_a0 = 1. / a0;
  auto const &gd = m_index_dim;
  // per axis: (local cell coordinate, squared distance of its slab from R)
  std::array<std::vector<std::pair<int, double>>, 3> ks;
  for (int d = 0; d < 3; ++d) {
    auto const &ax = m_index_axes[d];
    int const k0 = static_cast<int>(std::floor((R[d] - rr - m_index_shift[d]) * inv_a0));
    int const k1 = static_cast<int>(std::floor((R[d] + rr - m_index_shift[d]) * inv_a0));
    int const nk = m_grid[d]; // cells along d in the box (between the walls on a wall axis)
    bool const all = k1 - k0 + 1 >= nk || (ax.mode == 2 && (k0 < 0 || k1 >= nk));
    if (all) {
      for (int k = 0; k < gd[d]; ++k)
        ks[d].emplace_back(k, 0.);
      continue;
    }
    for (int k = k0; k <= k1; ++k) {
      double const lo = m_index_shift[d] + k * a0, hi = lo + a0;
      double const x = std::max(0., std::max(lo - R[d], R[d] - hi));
      double const x2 = x * x;
      if (ax.mode == 0) {
        ks[d].emplace_back(((k % nk) + nk) % nk, x2);
      } else if (ax.mode == 2) {
        int const l = k + 1 - ax.off;
        if (l >= 0 && l < ax.ext)
          ks[d].emplace_back(l, x2);
      } else {
        for (int img : {k - nk, k, k + nk})
          if (img - ax.off >= 0 && img - ax.off < ax.ext)
            ks[d].emplace_back(img - ax.off, x2);
      }
    }
  }
  double const rr2 = rr * rr;
  for (auto const &[kx, dx2] : ks[0])
    for (auto const &[ky, dy2] : ks[1]) {
      double const dxy2 = dx2 + dy2;
      if (dxy2 > rr2)
        continue;
      for (auto const &[kz, dz2] : ks[2]) {
        if (dxy2 + dz2 > rr2)
          continue;
        int const g = (kx * gd[1] + ky) * gd[2] + kz;
        for (int i = m_count[g]; i < m_count[g + 1]; ++i)
          out.push_back(i);
      }
    }
}

int Fluid::relocate_overlapping(System &s, std::uint64_t key) {
  m_ia = &s.interactions();
  auto const cols = colloids_of(s, *this);
  if (cols.empty())
    return 0;
  auto const &box = s.box();
  auto const &L = box.length();
  int moved = 0;
  std::string err;
  // the particles to check: all, or with the cell index of the last
  // collision those near a colloid and those bounced since
  bool const indexed = m_index_valid && static_cast<int>(m_hit.size()) == size();
  std::vector<int> cand;
  if (indexed) {
    for (auto const &c : cols) {
      double r = 0.;
      for (int t = 0; t < max_type; ++t)
        r = std::max(r, boundary(c.type, t).radius);
      near(c.R, r, L, cand);
    }
    cand.insert(cand.end(), m_loose.begin(), m_loose.end());
    std::sort(cand.begin(), cand.end());
    cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
  }
  int const n_check = indexed ? static_cast<int>(cand.size()) : size();
  for (int k = 0; k < n_check && err.empty(); ++k) {
    int const i = indexed ? cand[k] : k;
    for (int attempt = 0;; ++attempt) {
      bool inside = false;
      for (auto const &c : cols) {
        auto const b = boundary(c.type, type[i]);
        if (b.active && deep_inside(box.get_mi_vector(pos[i], c.R).norm2(), b.radius)) {
          inside = true;
          break;
        }
      }
      if (!inside)
        break;
      if (attempt == 0)
        ++moved;
      if (attempt > 10000) {
        err = "SRD: no free place found for particle " + std::to_string(id[i]) + ": the colloids fill the box";
        break;
      }
      auto const u = Utils::noise_uniform(m_p.seed, Utils::RNGSalt::srd_init, key,
                                          static_cast<std::uint64_t>(id[i]),
                                          1000 + static_cast<std::uint64_t>(attempt));
      for (int d = 0; d < 3; ++d)
        pos[i][d] = d == m_p.wall_axis ? wall_lo() + (u[d] + 0.5) * (wall_hi(L[d]) - wall_lo())
                                       : (u[d] + 0.5) * L[d];
      fold(pos[i], L);
    }
  }
  s.comm().throw_if_any(err);
  if (moved > 0)
    invalidate_index();
  return static_cast<int>(s.comm().sum(static_cast<long long>(moved)));
}

long long Fluid::global_size(System const &s) const { return s.comm().sum(static_cast<long long>(size())); }

void Fluid::add_particles(System const &s, int n, int t, double kT, std::uint64_t seed) {
  auto const &L = s.box().length();
  int next = 0;
  for (int x : id)
    next = std::max(next, x + 1);
  next = s.comm().max(next);
  int const first = size();
  int const me = s.comm().rank();
  double const sig = std::sqrt(kT / m_p.mass);
  Vector3d vm{};
  for (int k = 0; k < n; ++k) {
    int const pid = next + k;
    auto const u = Utils::noise_uniform(seed, Utils::RNGSalt::srd_init, 0, static_cast<std::uint64_t>(pid), 0);
    Vector3d x;
    for (int d = 0; d < 3; ++d)
      x[d] = d == m_p.wall_axis ? wall_lo() + (u[d] + 0.5) * (wall_hi(L[d]) - wall_lo()) : (u[d] + 0.5) * L[d];
    fold(x, L);
    auto const g = gauss4(seed, Utils::RNGSalt::srd_init, 1, static_cast<std::uint64_t>(pid), 0);
    Vector3d const vel = sig * Vector3d{g[0], g[1], g[2]};
    vm += vel;
    // every rank draws all of them (keyed by id) and keeps those in its domain
    if (const_cast<System &>(s).cells().owner_rank(x, s.box()) == me)
      pos.push_back(x), v.push_back(vel), id.push_back(pid), type.push_back(t);
  }
  if (n > 1) {
    vm *= 1. / static_cast<double>(n);
    for (int i = first; i < size(); ++i)
      v[i] -= vm;
  }
  invalidate_index();
  relocate_overlapping(const_cast<System &>(s), 0xadd0000ull + seed);
}

int Fluid::prepare(System &s) {
  m_ia = &s.interactions();
  try {
    check_geometry(s.box(), s.time_step());
  } catch (std::invalid_argument const &e) {
    throw Utils::RuntimeError(std::string("SRD cannot run: ") + e.what());
  }
  // a pair interaction set on an SRD type after the fluid was created would be ignored
  {
    std::vector<char> seen(max_type, 0);
    for (int t : type)
      seen[t] = 1;
    auto const &ia = s.interactions();
    for (int t = 0; t < std::min(max_type, ia.n_types()); ++t)
      for (int u = 0; seen[t] && u < ia.n_types(); ++u)
        if (ia.get(t, u).max_cut > 0.)
          throw Utils::RuntimeError("SRD cannot run: SRD type " + std::to_string(t) +
                                    " has a pair interaction with type " + std::to_string(u) +
                                    "; SRD particles take part in no pair interaction");
  }
  auto const cols = colloids_of(s, *this);
  for (auto const &c : cols) {
    for (int t = 0; t < max_type; ++t) {
      auto const b = boundary(c.type, t);
      if (b.active && b.rule != BoundaryRule::slip && !(c.I > 0.))
        throw Utils::RuntimeError(
            "SRD: colloid " + std::to_string(c.id) +
            " has a stick boundary rule but cannot rotate (set rotation=True and rinertia, "
            "e.g. 0.4 M a^2; needs feature ROTATION)");
    }
  }
  return relocate_overlapping(s, 0x5eed0000ull + s.step());
}

namespace {
// A bounce with the `pair` coupling (doc/srd.md, "Finite colloid mass"): the
// rule acts on the relative velocity u at the contact point; an impulse J
// (on the colloid, -J on the particle) changes it by -J_n/mu_n (normal) and
// -J_t/mu_t (tangential), 1/mu_n = 1/m + 1/M, 1/mu_t = 1/m + 1/M + a^2/I,
// and the pair's kinetic energy has the part u_n^2 mu_n/2 + u_t^2 mu_t/2 in
// these directions: drawing u' from the flux-weighted Maxwellian with these
// masses keeps the pair's Maxwellian. Returns J and the particle's new
// velocity. The noise is keyed by (seed, step, pid, k0/k1).
struct PairBounce {
  Vector3d J, vn;
};
PairBounce pair_rule(BoundaryParams const &b, double m, double M, double I, Vector3d const &V,
                     Vector3d const &W, Vector3d const &nrm, Vector3d const &v0, double kT,
                     std::uint64_t seed, std::uint64_t step, std::uint64_t pid, std::uint64_t k0,
                     std::uint64_t k1) {
  Vector3d const arm = b.radius * nrm;
  Vector3d t1 = std::abs(nrm[0]) < 0.9 ? cross(nrm, Vector3d{1., 0., 0.}) : cross(nrm, Vector3d{0., 1., 0.});
  t1 *= 1. / t1.norm();
  Vector3d const t2 = cross(nrm, t1);
  double const inv_mn = 1. / m + 1. / M;
  double const inv_mt = inv_mn + (I > 0. ? b.radius * b.radius / I : 0.);
  Vector3d const u = v0 - (V + cross(W, arm));
  double const un = u * nrm;
  Vector3d const ut = u - un * nrm;
  Vector3d J;
  if (b.rule == BoundaryRule::stochastic) {
    auto const g = gauss4(seed, Utils::RNGSalt::srd_wall, step, pid, k0);
    auto const x = Utils::philox_4x64(seed, Utils::RNGSalt::srd_wall, step, pid, k1);
    double const un2 = std::sqrt(kT * inv_mn) * std::sqrt(-2. * std::log(unit_open0(x[0])));
    double const st = std::sqrt(kT * inv_mt);
    Vector3d const ut2 = (st * g[0]) * t1 + (st * g[1]) * t2;
    J = ((un - un2) / inv_mn) * nrm + (1. / inv_mt) * (ut - ut2);
  } else if (b.rule == BoundaryRule::bounce_back) {
    J = (2. * un / inv_mn) * nrm + (2. / inv_mt) * ut;
  } else if (b.rule == BoundaryRule::rough) {
    double const cc = kRoughKeep, st = std::sqrt((1. - cc * cc) * kT * inv_mt);
    auto const g = gauss4(seed, Utils::RNGSalt::srd_wall, step, pid, k0);
    Vector3d const ut2 = cc * ut + (st * g[0]) * t1 + (st * g[1]) * t2;
    J = (2. * un / inv_mn) * nrm + (1. / inv_mt) * (ut - ut2);
  } else { // slip: specular reflection of the relative normal velocity
    J = un < 0. ? (2. * un / inv_mn) * nrm : Vector3d{};
  }
  return {J, v0 - J / m};
}
// Noise counters of the k-th bounce of a particle in one step (k = 0: the
// counters of the previous versions).
std::uint64_t key0(int k) { return k == 0 ? 0u : 16u + 2u * static_cast<std::uint64_t>(k); }
std::uint64_t key1(int k) { return key0(k) + 1u; }

// A pair (SRD particle, colloid j) that may meet within the step (event
// search, coupling pair): d0 = x_i(0) - R_j(0) (minimum image) at the start
// of the step, v the particle's velocity.
struct Cand {
  int pid, j, rank, index, type;
  Vector3d d0, v;
  double za; // x_i(0) along the wall axis (walled channels)
};
static_assert(std::is_trivially_copyable_v<Cand>);
constexpr int kMaxEventBounces = 8; // per particle and step (then the end-of-step check)

// Channel walls (planes x[a] = z0, z1, fixed-surface rules in the frame of
// the moving wall; doc/srd.md "Channel walls").
struct WallGeom {
  int a;
  double z0, z1, sig, m;
  BoundaryRule rule;
  Vector3d v_lo, v_hi;
  std::uint64_t seed;
};
// The channel walls of fluid f in a box of edges L (f has walls: wall_axis >= 0).
WallGeom wall_geom(Fluid const &f, Vector3d const &L) {
  auto const &p = f.params();
  int const a = p.wall_axis;
  return {a, f.wall_lo(), f.wall_hi(L[a]), std::sqrt(p.kT / p.mass), p.mass,
          static_cast<BoundaryRule>(p.wall_rule), p.wall_v_lo, p.wall_v_hi, p.seed};
}
// The new velocity of a particle with velocity v0 hitting the lower (lo) or
// upper wall in its bounce-th wall bounce of the step (noise keyed by
// (seed, step, pid, key_base + 2 + bounce / key_base + 8 + bounce); key_base
// 0 for the flight between the walls, kFallbackWallKeys for the half step
// after an end-of-step colloid bounce).
constexpr std::uint64_t kFallbackWallKeys = 64;
Vector3d wall_rule(WallGeom const &g, std::uint64_t step, std::uint64_t pid, int bounce, bool lo,
                   Vector3d const &v0, std::uint64_t key_base = 0) {
  int const a = g.a;
  Vector3d nrm{};
  nrm[a] = lo ? 1. : -1.; // into the fluid
  Vector3d const vw = lo ? g.v_lo : g.v_hi;
  Vector3d vn;
  Vector3d const vr = v0 - vw;
  double const vrn = vr * nrm;
  if (g.rule == BoundaryRule::stochastic) {
    auto const gs = gauss4(g.seed, Utils::RNGSalt::srd_wall, step, pid, key_base + 2 + bounce);
    auto const u = Utils::philox_4x64(g.seed, Utils::RNGSalt::srd_wall, step, pid, key_base + 8 + bounce);
    vn = vw + (g.sig * std::sqrt(-2. * std::log(unit_open0(u[0])))) * nrm;
    int const t1 = (a + 1) % 3, t2 = (a + 2) % 3;
    vn[t1] += g.sig * gs[0];
    vn[t2] += g.sig * gs[1];
  } else if (g.rule == BoundaryRule::bounce_back || g.rule == BoundaryRule::rough) {
    vn = 2. * vw - v0;
  } else { // slip
    vn = v0 - (2. * vrn) * nrm;
  }
  return vn;
}
constexpr int kMaxWallBounces = 4; // per particle and step
// Streams one particle by dt between the walls (x, v updated, the momentum
// handed to each wall added, vmax raised by the new speeds); on_bounce(t, x,
// v') is called after each wall bounce (t: time within the step).
template <class OnBounce>
void wall_flight(WallGeom const &g, std::uint64_t step, std::uint64_t pid, double dt, Vector3d &x, Vector3d &v,
                 Vector3d &to_lo, Vector3d &to_hi, double &vmax, OnBounce &&on_bounce, std::uint64_t key_base = 0) {
  int const a = g.a;
  double const z0 = g.z0, z1 = g.z1;
  double t_left = dt;
  for (int bounce = 0; bounce < kMaxWallBounces; ++bounce) {
    double const z = x[a] + t_left * v[a];
    if (z >= z0 && z < z1)
      break;
    bool const lo = z < z0;
    double const tc = std::clamp(((lo ? z0 : z1) - x[a]) / v[a], 0., t_left);
    x += tc * v;
    x[a] = lo ? z0 : std::nextafter(z1, z0);
    t_left -= tc;
    Vector3d const vn = wall_rule(g, step, pid, bounce, lo, v, key_base);
    (lo ? to_lo : to_hi) += g.m * (v - vn);
    v = vn;
    vmax = std::max(vmax, vn.norm()); // the colloid search's displacement bound
    on_bounce(dt - t_left, x, v);
  }
  x += t_left * v;
  if (x[a] < z0 || x[a] >= z1) // pathological: still outside
    x[a] = std::clamp(x[a], z0, std::nextafter(z1, z0));
}
// A particle's flight between the walls within one step without colloids:
// segments (start time, position, velocity; positions not folded), its end
// state and the momentum it hands to the walls.
struct WallPath {
  int i, nseg;
  std::array<double, kMaxWallBounces + 1> t;
  std::array<Vector3d, kMaxWallBounces + 1> x, v;
  Vector3d x_end, v_end, to_lo, to_hi;
  bool used; // its end state and momenta are taken (no colloid bounce)
};
} // namespace

void Fluid::stream(System &s, double dt) {
  m_ia = &s.interactions();
  m_leave_valid = false;
  auto const &box = s.box();
  auto const &L = box.length();
  int const n = size();
  if (drive.on) {
    double const h = 0.5 * L[drive.grad_dir];
    for (int i = 0; i < n; ++i)
      v[i][drive.flow_dir] += (pos[i][drive.grad_dir] < h ? drive.g : -drive.g) * dt;
    m_vmax += std::abs(drive.g) * dt;
  }
  if (drive.accel.norm2() > 0.) {
    for (int i = 0; i < n; ++i)
      v[i] += dt * drive.accel;
    m_vmax += drive.accel.norm() * dt;
  }
  auto cols = colloids_of(s, *this);
  // Walled channel with colloids of the pair coupling: the wall bounces are
  // events of the event search (1.) too. Every particle's flight between the
  // walls is computed here (the particles that hit a wall, with their path,
  // in wpath), but the particles stay at their positions of the start of the
  // step; those without a colloid bounce take the end state of that flight.
  bool wall_events = false;
  if (m_p.wall_axis >= 0) {
    int const nt0 = std::min(max_type, s.interactions().n_types());
    for (auto const &c : cols)
      for (int t = 0; t < nt0 && !wall_events; ++t) {
        auto const b = boundary(c.type, t);
        wall_events = b.active && b.coupling == Coupling::pair && b.radius > 0.;
      }
  }
  std::vector<WallPath> wpath;
  WallGeom wg{};
  if (wall_events) {
    int const a = m_p.wall_axis;
    wg = wall_geom(*this, L);
    if (static_cast<int>(m_wslot.size()) != n)
      m_wslot.assign(static_cast<std::size_t>(n), -1);
    for (int i = 0; i < n; ++i) {
      double const z = pos[i][a] + dt * v[i][a]; // wall_flight's first test
      if (z >= wg.z0 && z < wg.z1)
        continue;
      WallPath w;
      w.i = i, w.nseg = 1, w.t[0] = 0., w.x[0] = pos[i], w.v[0] = v[i];
      w.x_end = pos[i], w.v_end = v[i], w.to_lo = Vector3d{}, w.to_hi = Vector3d{}, w.used = true;
      wall_flight(wg, s.step(), static_cast<std::uint64_t>(id[i]), dt, w.x_end, w.v_end, w.to_lo, w.to_hi,
                  m_vmax, [&w](double t, Vector3d const &x, Vector3d const &vv) {
                    w.t[w.nseg] = t, w.x[w.nseg] = x, w.v[w.nseg] = vv;
                    ++w.nseg;
                  });
      m_wslot[i] = static_cast<int>(wpath.size());
      wpath.push_back(w);
    }
  } else if (m_p.wall_axis >= 0) {
    walls(s.step(), dt, L); // streams every particle by dt, reflecting at the walls
  }
  m_disp += m_vmax * dt;    // bound on the displacement since the last collision
  double const dt_free = m_p.wall_axis >= 0 && !wall_events ? 0. : dt; // walls() streamed already
  if (cols.empty()) {
    // on several ranks, before a collision: list the particles that leave
    // this rank's domain (for the migration; no pass of its own)
    bool const track = s.comm().parallel() && m_n_tau > 0 &&
                       (m_n_streams + 1) % static_cast<std::uint64_t>(m_n_tau) == 0;
    if (!track) {
      for (int i = 0; i < n; ++i) {
        pos[i] += dt_free * v[i];
        fold(pos[i], L);
      }
      return;
    }
    auto const dom = domain_box(s);
    double const lo0 = dom[0].first, hi0 = dom[0].second, lo1 = dom[1].first, hi1 = dom[1].second,
                 lo2 = dom[2].first, hi2 = dom[2].second;
    m_leave.clear();
    for (int i = 0; i < n; ++i) {
      pos[i] += dt_free * v[i];
      fold(pos[i], L);
      auto const &x = pos[i];
      if (!(x[0] >= lo0 && x[0] < hi0 && x[1] >= lo1 && x[1] < hi1 && x[2] >= lo2 && x[2] < hi2)) [[unlikely]]
        m_leave.push_back(i);
    }
    m_leave_valid = true;
    return;
  }
  auto &ps = s.particles();
  std::uint64_t const step = s.step();
  int const me = s.comm().rank();
  double const m = m_p.mass, kT = m_p.kT;
  // the srd_boundary kernels of the types in use, looked up once per step
  int const nt = std::min(max_type, s.interactions().n_types());
  std::vector<BoundaryParams> btab(static_cast<std::size_t>(nt) * static_cast<std::size_t>(nt));
  for (int c = 0; c < nt; ++c)
    for (int t = 0; t < nt; ++t)
      btab[static_cast<std::size_t>(c) * nt + t] = boundary(c, t);
  BoundaryParams const none{};
  auto bnd = [&](int c, int t) -> BoundaryParams const & {
    return c >= 0 && t >= 0 && c < nt && t < nt ? btab[static_cast<std::size_t>(c) * nt + t] : none;
  };
  // the colloid centres folded into the box (minimum images by one wrap)
  std::vector<Vector3d> Rf(cols.size());
  for (std::size_t j = 0; j < cols.size(); ++j) {
    Rf[j] = cols[j].R;
    fold(Rf[j], L);
  }
  double r_max = 0.;
  std::vector<double> r_pair(cols.size(), 0.); // largest radius with the pair coupling
  for (std::size_t j = 0; j < cols.size(); ++j)
    for (int t = 0; t < nt; ++t) {
      auto const &b = bnd(cols[j].type, t);
      r_max = std::max(r_max, b.radius);
      if (b.active && b.coupling == Coupling::pair)
        r_pair[j] = std::max(r_pair[j], b.radius);
    }
  double const r_search = r_max;
  bool const small_box = !(r_max < 0.5 * L[0] - 1.) && r_max > 0.; // no quick rejection
  std::uint64_t const stamp = m_n_streams + 1;
  bool const indexed = m_index_valid && static_cast<int>(m_hit.size()) == n;
  std::vector<Vector3d> dP(cols.size());
  // bounces of this step per particle (pid, count; ascending pid), for the noise counters
  std::vector<std::pair<int, int>> n_bounces;

  // 1. Event-ordered bounces (coupling pair). The colloid moved in the MD drift from
  // R0 = R - V dt with its velocity V; the SRD particles are still at their
  // positions x(0) of the start of the step. Every (particle, colloid) pair
  // whose relative straight path within the step comes closer than
  // radius + margin is a candidate; the candidates of all ranks are gathered
  // on every rank and every rank runs the same event sequence: the earliest
  // crossing of the sphere by the relative linear motion of particle and
  // colloid (both move on straight lines between events), the rule applied
  // at that time on the surface, the colloid's new V, Omega used for the
  // rest of the step (its later crossings recomputed), the particle
  // streamed on with its new velocity. The colloid ends at R0 + the
  // integral of its piecewise constant velocity (its position is corrected
  // by sum_k dV_k (dt - t_k)). A particle the colloid's velocity change
  // brings into reach that was no candidate (the margin is 0.1 a0) is caught
  // by the end-of-step check (2.), which applies the rule of the previous
  // versions. In a walled channel a particle's path within the step is
  // broken at the walls: the candidate test follows its flight between the
  // walls (wpath), and its wall bounces are events of the same sequence (at
  // the time its straight path reaches a plane; the wall rule with the noise
  // of its k-th wall bounce, as in walls()).
  std::vector<Vector3d> dR(cols.size());
  std::vector<std::pair<int, std::array<Vector3d, 2>>> moved; // this rank's bounced particles
  bool events = true;
  if (events) {
    bool any = false;
    for (double r : r_pair)
      any |= r > 0.;
    events = any; // the same on every rank (the colloids are gathered)
  }
  std::vector<char> narrow(cols.size(), 0), all_pair(cols.size(), 1);
  std::vector<std::vector<int>> cand_of(cols.size()); // this rank's candidates of colloid j
  for (std::size_t j = 0; j < cols.size(); ++j)
    for (int t = 0; t < nt; ++t) {
      auto const &b = bnd(cols[j].type, t);
      if (b.active && b.coupling != Coupling::pair)
        all_pair[j] = 0;
    }
  if (events) {
    double const margin = 0.1 * m_p.cell_size;
    std::vector<Vector3d> R0(cols.size());
    for (std::size_t j = 0; j < cols.size(); ++j) {
      R0[j] = cols[j].R - dt * cols[j].V;
      fold(R0[j], L);
    }
    std::vector<Cand> cand;
    // quick rejection in the indexed search: a particle that is not loose
    // moves no faster than m_vmax in this step (walls and drive included), so
    // one farther than radius + margin + (m_vmax + |V|) dt from R0 cannot
    // come within radius + margin (the slack 1e-9 keeps the exact test's
    // round-off out of it: the same candidates)
    std::vector<double> reach2(cols.size(), 0.);
    for (std::size_t j = 0; j < cols.size(); ++j) {
      double const reach = (r_pair[j] + margin + (m_vmax + cols[j].V.norm()) * dt) * (1. + 1e-9);
      reach2[j] = reach * reach;
    }
    auto consider = [&](int i, std::size_t j, bool quick) {
      Vector3d const d0 = mi_folded(pos[i], R0[j], L);
      if (quick && d0.norm2() > reach2[j])
        return;
      auto const &b = bnd(cols[j].type, type[i]);
      if (!b.active || b.coupling != Coupling::pair)
        return;
      double const rr = b.radius + margin;
      int const ws = wall_events ? m_wslot[i] : -1;
      if (ws < 0) {
        Vector3d const w = v[i] - cols[j].V;
        double const w2 = w.norm2();
        double const t = w2 > 0. ? std::clamp(-(d0 * w) / w2, 0., dt) : 0.;
        if ((d0 + t * w).norm2() < rr * rr)
          cand.push_back({id[i], static_cast<int>(j), me, i, type[i], d0, v[i], wall_events ? pos[i][wg.a] : 0.});
        return;
      }
      // a particle that hits a wall: every straight piece of its flight
      auto const &wp = wpath[static_cast<std::size_t>(ws)];
      for (int sg = 0; sg < wp.nseg; ++sg) {
        double const ta = wp.t[sg], tb = sg + 1 < wp.nseg ? wp.t[sg + 1] : dt;
        Vector3d const ds = d0 + (wp.x[sg] - wp.x[0]) - ta * cols[j].V;
        Vector3d const w = wp.v[sg] - cols[j].V;
        double const w2 = w.norm2();
        double const t = w2 > 0. ? std::clamp(-(ds * w) / w2, 0., std::max(0., tb - ta)) : 0.;
        if ((ds + t * w).norm2() < rr * rr) {
          cand.push_back({id[i], static_cast<int>(j), me, i, type[i], d0, v[i], pos[i][wg.a]});
          return;
        }
      }
    };
    if (indexed) {
      // a candidate is, at some time of the step, within radius + margin of
      // R0 + V t, hence within radius + margin + |V| dt of R
      std::vector<int> near_list;
      for (std::size_t j = 0; j < cols.size(); ++j) {
        if (!(r_pair[j] > 0.))
          continue;
        near_list.clear();
        near(cols[j].R, r_pair[j] + margin + cols[j].V.norm() * dt, L, near_list);
        for (int i : near_list)
          if (!m_is_loose[i])
            consider(i, j, true);
      }
      for (int i : m_loose)
        for (std::size_t j = 0; j < cols.size(); ++j)
          if (r_pair[j] > 0.)
            consider(i, j, false);
    } else {
      for (int i = 0; i < n; ++i)
        for (std::size_t j = 0; j < cols.size(); ++j) {
          if (!(r_pair[j] > 0.))
            continue;
          if (!small_box && !(wall_events && m_wslot[i] >= 0)) {
            // quick rejection along x (one wrap: r + reach < L/2; not for a
            // particle whose velocity a wall changes within the step)
            double dx = pos[i][0] - R0[j][0];
            dx = dx > 0.5 * L[0] ? dx - L[0] : (dx < -0.5 * L[0] ? dx + L[0] : dx);
            if (std::abs(dx) >= r_pair[j] + margin + (std::abs(v[i][0]) + std::abs(cols[j].V[0])) * dt)
              continue;
          }
          consider(i, j, false);
        }
    }
    if (s.comm().parallel())
      cand = s.comm().allgatherv(cand);
    std::sort(cand.begin(), cand.end(),
              [](Cand const &a, Cand const &b) { return a.pid < b.pid || (a.pid == b.pid && a.j < b.j); });
    // the particles (one state per pid) and the colloids' states
    struct PState {
      int k0, k1, nb = 0, ver = 0, nw = 0; // nw: wall bounces
      Vector3d v, X{}; // velocity, displacement at time tp
      double tp = 0.;
      double za = 0.;                 // x(0) along the wall axis
      Vector3d to_lo{}, to_hi{};      // momentum handed to the walls
    };
    struct CState {
      Vector3d D{}, V, W; // displacement at time tc, velocity, angular velocity
      double tc = 0.;
      int ver = 0;
      double dv = 0.; // largest |V - V(0)| within the step
      double A = 0.;  // sum of |dV| (dt - t) over its events so far
      std::vector<int> pairs;
    };
    std::vector<PState> P;
    std::vector<int> p_of(cand.size());
    for (std::size_t k = 0; k < cand.size(); ++k) {
      if (k == 0 || cand[k].pid != cand[k - 1].pid) {
        PState ps0;
        ps0.k0 = static_cast<int>(k);
        ps0.v = cand[k].v;
        ps0.za = cand[k].za;
        P.push_back(ps0);
      }
      P.back().k1 = static_cast<int>(k) + 1;
      p_of[k] = static_cast<int>(P.size()) - 1;
    }
    std::vector<CState> C(cols.size());
    std::vector<double> rad(cand.size());
    for (std::size_t j = 0; j < cols.size(); ++j)
      C[j].V = cols[j].V, C[j].W = cols[j].W;
    for (std::size_t k = 0; k < cand.size(); ++k) {
      C[cand[k].j].pairs.push_back(static_cast<int>(k));
      rad[k] = bnd(cols[cand[k].j].type, cand[k].type).radius;
    }
    struct Ev {
      double t;
      int pid, j, k, vp, vc;
      bool operator>(Ev const &o) const {
        return t > o.t || (t == o.t && (pid > o.pid || (pid == o.pid && j > o.j)));
      }
    };
    std::vector<Ev> heap;
    // Per pair, when its last computation found no crossing within the step:
    // clr = its smallest distance from contact over the rest of the step,
    // acc0 = the colloid's A then (else clr = -1). While the particle keeps
    // its velocity, the colloid's velocity changes since then move the pair's
    // relative path by at most A - acc0 (the sum of |dV| (dt - t) over them),
    // so a pair with clr > A - acc0 still has no crossing and its recomputation
    // after a velocity change of the colloid is skipped (it would schedule
    // nothing: the same sequence of events; the slack 1e-9 radius keeps
    // round-off out of it).
    std::vector<double> clr(cand.size(), -1.), acc0(cand.size(), 0.);
    auto schedule = [&](int k, double t_now) {
      auto const &c = cand[k];
      auto const &p = P[p_of[k]];
      auto const &cs = C[c.j];
      clr[k] = -1.;
      if (p.nb >= kMaxEventBounces)
        return;
      Vector3d const dn = c.d0 + (p.X + (t_now - p.tp) * p.v) - (cs.D + (t_now - cs.tc) * cs.V);
      Vector3d const w = p.v - cs.V;
      double const bb = dn * w;
      if (bb < 0.) { // approaching
        double const cc = dn.norm2() - rad[k] * rad[k];
        double const disc = bb * bb - w.norm2() * cc;
        if (disc >= 0.) { // else it passes by
          // the entry root, stable form (c / (larger root)); 0 if inside already
          double const t = t_now + (cc <= 0. ? 0. : cc / (-bb + std::sqrt(disc)));
          if (t <= dt) {
            heap.push_back({t, c.pid, c.j, k, p.ver, cs.ver});
            std::push_heap(heap.begin(), heap.end(), std::greater<Ev>{});
            return;
          }
        }
      }
      double const w2 = w.norm2();
      double const s = w2 > 0. ? std::clamp(-bb / w2, 0., std::max(0., dt - t_now)) : 0.;
      clr[k] = (dn + s * w).norm() - rad[k];
      acc0[k] = cs.A;
    };
    // walled channel: the particle's next wall bounce (j = -1, k = its state)
    auto schedule_wall = [&](int pi, double t_now) {
      auto const &p = P[static_cast<std::size_t>(pi)];
      int const a = wg.a;
      double const vz = p.v[a];
      if (p.nw >= kMaxWallBounces || vz == 0.)
        return;
      double const z = p.za + p.X[a] + (t_now - p.tp) * vz;
      double const t = t_now + std::max(0., ((vz < 0. ? wg.z0 : wg.z1) - z) / vz);
      if (!(t <= dt))
        return;
      heap.push_back({t, cand[static_cast<std::size_t>(p.k0)].pid, -1, pi, p.ver, 0});
      std::push_heap(heap.begin(), heap.end(), std::greater<Ev>{});
    };
    for (std::size_t k = 0; k < cand.size(); ++k)
      schedule(static_cast<int>(k), 0.);
    if (wall_events)
      for (std::size_t pi = 0; pi < P.size(); ++pi)
        schedule_wall(static_cast<int>(pi), 0.);
    while (!heap.empty()) {
      std::pop_heap(heap.begin(), heap.end(), std::greater<Ev>{});
      Ev const e = heap.back();
      heap.pop_back();
      if (e.j < 0) { // a wall bounce (the fixed-surface wall rule)
        auto &p = P[static_cast<std::size_t>(e.k)];
        if (p.ver != e.vp || p.nw >= kMaxWallBounces)
          continue; // outdated
        int const a = wg.a;
        double const t = e.t;
        p.X += (t - p.tp) * p.v;
        p.tp = t;
        bool const lo = p.v[a] < 0.;
        p.X[a] = (lo ? wg.z0 : std::nextafter(wg.z1, wg.z0)) - p.za;
        Vector3d const vn = wall_rule(wg, step, static_cast<std::uint64_t>(e.pid), p.nw, lo, p.v);
        (lo ? p.to_lo : p.to_hi) += m * (p.v - vn);
        p.v = vn;
        ++p.nw, ++p.ver;
        for (int k2 = p.k0; k2 < p.k1; ++k2) // its new velocity: its colloids
          schedule(k2, t);
        schedule_wall(e.k, t);
        continue;
      }
      auto &p = P[p_of[e.k]];
      auto &cs = C[e.j];
      if (p.ver != e.vp || cs.ver != e.vc || p.nb >= kMaxEventBounces)
        continue; // outdated
      auto const &c = cand[e.k];
      auto const &col = cols[e.j];
      double const t = e.t;
      cs.D += (t - cs.tc) * cs.V;
      cs.tc = t;
      p.X += (t - p.tp) * p.v;
      p.tp = t;
      Vector3d const dn = c.d0 + p.X - cs.D;
      double const r = dn.norm();
      Vector3d const nrm = r > 0. ? dn / r : Vector3d{0., 0., 1.};
      auto const &b = bnd(col.type, c.type);
      Vector3d const arm = b.radius * nrm;
      p.X = cs.D + arm - c.d0; // on the surface
      auto const bo = pair_rule(b, m, col.M, col.I, cs.V, cs.W, nrm, p.v, kT, m_p.seed, step,
                                static_cast<std::uint64_t>(c.pid), key0(p.nb), key1(p.nb));
      cs.V += bo.J / col.M;
      cs.A += (bo.J / col.M).norm() * (dt - t);
      cs.dv = std::max(cs.dv, (cs.V - col.V).norm());
      if (col.I > 0.)
        cs.W += cross(arm, bo.J) / col.I;
      dP[e.j] += bo.J;
      p.v = bo.vn;
      ++p.nb, ++p.ver, ++cs.ver;
      clr[e.k] = -1.; // the particle's new velocity (not recomputed now)
      for (int k2 : cs.pairs) // the colloid's new velocity: its other pairs
        if (k2 != e.k) {
          if (clr[k2] - (cs.A - acc0[k2]) > 1e-9 * rad[k2])
            continue; // no crossing possible before the end of the step
          schedule(k2, t);
        }
      for (int k2 = p.k0; k2 < p.k1; ++k2) // the particle's new velocity: its other colloids
        if (k2 != e.k)
          schedule(k2, t);
      if (wall_events)
        schedule_wall(p_of[e.k], t);
    }
    for (std::size_t j = 0; j < cols.size(); ++j) {
      auto &cs = C[j];
      cs.D += (dt - cs.tc) * cs.V;
      dR[j] = cs.D - dt * cols[j].V; // exactly 0 without bounces
      cols[j].R += dR[j];
      cols[j].V = cs.V, cols[j].W = cs.W;
      // A particle that was no candidate of colloid j came no closer than
      // radius + margin to R0 + V(0) t; the colloid's path deviates from that
      // by at most dt max|V - V(0)|: below margin/2, no such particle can end
      // inside it, and the end-of-step check of j needs only its candidates
      // (and the bounced particles, checked against every colloid anyway)
      narrow[j] = all_pair[j] && dt * cs.dv < 0.5 * margin;
    }
    for (std::size_t k = 0; k < cand.size(); ++k)
      if (cand[k].rank == me && narrow[cand[k].j])
        cand_of[cand[k].j].push_back(cand[k].index);
    for (auto const &p : P) {
      if (p.nb == 0)
        continue;
      auto const &c = cand[p.k0];
      n_bounces.emplace_back(c.pid, p.nb);
      if (c.rank == me) {
        moved.push_back({c.index, std::array<Vector3d, 2>{pos[c.index] + p.X + (dt - p.tp) * p.v, p.v}});
        if (wall_events) { // its flight of the event sequence replaces wpath's
          momentum_to_wall_lo += p.to_lo;
          momentum_to_wall_hi += p.to_hi;
          if (m_wslot[c.index] >= 0)
            wpath[static_cast<std::size_t>(m_wslot[c.index])].used = false;
        }
      }
    }
  }
  auto bounces_of = [&](int pid) {
    auto const it = std::lower_bound(n_bounces.begin(), n_bounces.end(), std::make_pair(pid, 0));
    return it != n_bounces.end() && it->first == pid ? it->second : 0;
  };

  // 2. End-of-step check: the SRD particles found inside a colloid after
  // streaming (each at most once per step, off the first colloid in id
  // order that holds it): every bounce of the `fixed_surface` and `seed003`
  // couplings (seed 003's rule: half a step back, onto the surface), and
  // with the pair coupling (also in walled channels, since 2026-12-01) only a
  // particle the event search did not foresee.
  for (int i = 0; i < n; ++i) {
    pos[i] += dt_free * v[i];
    fold(pos[i], L);
  }
  for (auto &w : wpath) { // walled channel: the flights between the walls
    pos[w.i] = w.x_end, v[w.i] = w.v_end;
    fold(pos[w.i], L);
    m_wslot[w.i] = -1;
    if (w.used)
      momentum_to_wall_lo += w.to_lo, momentum_to_wall_hi += w.to_hi;
  }
  for (auto const &mv : moved) {
    int const i = mv.first;
    pos[i] = mv.second[0], v[i] = mv.second[1];
    fold(pos[i], L);
    if (wall_events) { // a straight piece may have ended past a wall by round-off
      int const a = wg.a;
      if (pos[i][a] < wg.z0 || pos[i][a] >= wg.z1)
        pos[i][a] = std::clamp(pos[i][a], wg.z0, std::nextafter(wg.z1, wg.z0));
    }
  }
  for (std::size_t j = 0; j < cols.size(); ++j) { // the centres after the events
    Rf[j] = cols[j].R;
    fold(Rf[j], L);
  }
  double const r_rej = small_box ? INFINITY : r_max;
  std::vector<Hit> hits;
  auto inside = [&](int i, std::size_t j) {
    auto const &c = cols[j];
    auto const &b = bnd(c.type, type[i]);
    if (!b.active)
      return false;
    Vector3d const d = mi_folded(pos[i], Rf[j], L);
    if (events && b.coupling == Coupling::pair ? !deep_inside(d.norm2(), b.radius)
                                               : d.norm2() >= b.radius * b.radius)
      return false;
    hits.push_back({id[i], static_cast<int>(j), me, i, type[i], d, v[i]});
    return true;
  };
  if (indexed) {
    // the cell index of the last collision: a particle now within r of a
    // colloid sat, at the sort, in a cell within r + m_disp of it; the
    // particles bounced since the sort (m_loose) are checked one by one
    for (auto const &mv : moved) // their displacement is no longer bounded by m_disp
      if (!m_is_loose[mv.first]) {
        m_is_loose[mv.first] = 1;
        m_loose.push_back(mv.first);
      }
    std::vector<int> cand;
    for (std::size_t j = 0; j < cols.size(); ++j) {
      cand.clear();
      if (narrow[j])
        cand = cand_of[j];
      else
        near(cols[j].R, r_search, L, cand);
      for (int i : cand)
        if (m_hit[i] != stamp && inside(i, j))
          m_hit[i] = stamp;
    }
    for (std::size_t k = 0; k < m_loose.size(); ++k) {
      int const i = m_loose[k];
      if (m_hit[i] == stamp)
        continue;
      for (std::size_t j = 0; j < cols.size(); ++j)
        if (inside(i, j)) {
          m_hit[i] = stamp;
          break;
        }
    }
    for (auto const &h : hits)
      if (!m_is_loose[h.index]) {
        m_is_loose[h.index] = 1;
        m_loose.push_back(h.index);
      }
  } else {
    for (int i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < cols.size(); ++j) {
        // quick rejection along x: pos and the folded centre differ by less
        // than L + v dt, so one wrap gives the minimum image whenever it is
        // shorter than r_max < L/2
        double dx = pos[i][0] - Rf[j][0];
        dx = dx > 0.5 * L[0] ? dx - L[0] : (dx < -0.5 * L[0] ? dx + L[0] : dx);
        if (std::abs(dx) >= r_rej)
          continue;
        if (inside(i, j))
          break;
      }
    }
  }
  // The end-of-step bounces of all ranks, in the order of the SRD ids: every
  // rank applies them in this order to its copy of the colloids
  // (bit-identical on every rank, whichever rank holds the particles and
  // whichever search found them) and updates its own particles.
  if (s.comm().parallel())
    hits = s.comm().allgatherv(hits);
  std::sort(hits.begin(), hits.end(), [](Hit const &a, Hit const &b) { return a.pid < b.pid; });
  std::vector<Vector3d> V(cols.size()), W(cols.size()), dP_late(cols.size()), dL_late(cols.size());
  for (std::size_t j = 0; j < cols.size(); ++j)
    V[j] = cols[j].V, W[j] = cols[j].W;
  for (auto const &h : hits) {
    auto const &c = cols[h.j];
    auto const &b = bnd(c.type, h.type);
    bool const pair = b.coupling == Coupling::pair;
    Vector3d const &v0 = h.v;
    // seed 003: half a step back, onto the surface along the shortest vector
    // (pair: in the frame of the colloid, which moved by V dt in this step)
    Vector3d const d = h.d - (0.5 * dt) * (pair ? v0 - c.V : v0);
    double const r = d.norm();
    Vector3d const nrm = r > 0. ? d / r : Vector3d{0., 0., 1.};
    Vector3d const arm = b.radius * nrm; // r* - R
    auto const pid = static_cast<std::uint64_t>(h.pid);
    int const nb = bounces_of(h.pid);
    Vector3d J, vn; // impulse handed to the colloid, new velocity of the particle
    if (pair) {
      auto const bo = pair_rule(b, m, c.M, c.I, V[h.j], W[h.j], nrm, v0, kT, m_p.seed, step, pid, key0(nb), key1(nb));
      J = bo.J, vn = bo.vn;
    } else {
      // the rule in the frame of an infinitely heavy surface (seed 003)
      double const sig = std::sqrt(kT / m);
      Vector3d const vloc = V[h.j] + cross(W[h.j], arm);
      Vector3d t1 = std::abs(nrm[0]) < 0.9 ? cross(nrm, Vector3d{1., 0., 0.}) : cross(nrm, Vector3d{0., 1., 0.});
      t1 *= 1. / t1.norm();
      Vector3d const t2 = cross(nrm, t1);
      if (b.rule == BoundaryRule::stochastic) {
        // eqs. (1), (2) about the surface velocity: flux-weighted normal
        // (Rayleigh) and Maxwellian tangential components
        auto const g = gauss4(m_p.seed, Utils::RNGSalt::srd_wall, step, pid, key0(nb));
        auto const x = Utils::philox_4x64(m_p.seed, Utils::RNGSalt::srd_wall, step, pid, key1(nb));
        double const v_n = sig * std::sqrt(-2. * std::log(unit_open0(x[0])));
        vn = vloc + v_n * nrm + (sig * g[0]) * t1 + (sig * g[1]) * t2;
      } else if (b.rule == BoundaryRule::bounce_back) {
        vn = 2. * vloc - v0;
      } else if (b.rule == BoundaryRule::rough) {
        // mean tangential transfer of a rough-sphere collision (fraction 2K
        // of the relative tangential velocity reversed); the rest redrawn
        // from the Maxwellian so the rule keeps detailed balance
        double const cc = kRoughKeep, s_noise = std::sqrt(1. - cc * cc) * sig;
        auto const g = gauss4(m_p.seed, Utils::RNGSalt::srd_wall, step, pid, key0(nb));
        Vector3d const vr = v0 - vloc;
        Vector3d const vr_n = (vr * nrm) * nrm;
        vn = vloc - vr_n + cc * (vr - vr_n) + (s_noise * g[0]) * t1 + (s_noise * g[1]) * t2;
      } else {
        double const vr = (v0 - vloc) * nrm;
        vn = vr < 0. ? v0 - (2. * vr) * nrm : v0;
      }
      J = m * (v0 - vn);
    }
    Vector3d const Lj = cross(arm, J);
    dP[h.j] += J;
    if (b.coupling == Coupling::seed003) { // applied at the end of the step
      dP_late[h.j] += J;
      dL_late[h.j] += Lj;
    } else { // at once: the next bounce sees the new V, Omega
      V[h.j] += J / c.M;
      if (c.I > 0.)
        W[h.j] += Lj / c.I;
    }
    if (h.rank != me)
      continue;
    int const i = h.index;
    Vector3d const x_end = pos[i]; // where the step left it: h.d = x_end - R (minimum image)
    v[i] = vn;
    pos[i] = c.R + arm + (0.5 * dt) * (pair ? vn - c.V : vn);
    if (m_p.wall_axis >= 0) {
      // Walled channel: the half step after the bounce must not take the
      // particle through a wall (a colloid near a wall; the walls are not
      // periodic, so follow it in its own image). Only if it would, the half
      // step is streamed again by the wall flight (exact crossing, the wall
      // rule with noise counters of its own), so scenes where it would not
      // keep their bits.
      WallGeom const wg_fb = wall_geom(*this, L);
      int const a = wg_fb.a;
      double const z0 = wg_fb.z0, z1 = wg_fb.z1;
      Vector3d x = x_end - h.d + arm; // the contact point, colloid at its end-of-step place
      if (pair)
        x -= (0.5 * dt) * c.V; // ... at the middle of the step (the pair rule's frame)
      double const z = x[a] + 0.5 * dt * vn[a];
      if (!(z >= z0 && z < z1)) {
        x[a] = std::clamp(x[a], z0, std::nextafter(z1, z0)); // a colloid reaching past a wall
        Vector3d vv = vn;
        wall_flight(wg_fb, step, pid, 0.5 * dt, x, vv, momentum_to_wall_lo, momentum_to_wall_hi, m_vmax,
                    [](double, Vector3d const &, Vector3d const &) {}, kFallbackWallKeys);
        pos[i] = x, v[i] = vv;
      }
    }
    fold(pos[i], L);
  }
  for (std::size_t j = 0; j < cols.size(); ++j) {
    momentum_to_colloids += dP[j];
    int const k = cols[j].index;
    if (k < 0)
      continue; // owned by another rank
    ps.pos[k] += dR[j];
    ps.v[k] = V[j] + dP_late[j] / cols[j].M;
#ifdef ROTATION
    if (cols[j].I > 0.)
      ps.omega[k] = W[j] + dL_late[j] / cols[j].I;
#endif
  }
}
// Channel walls at x[a] = 0 and L: exact crossing time (planes are cheap),
// the boundary rule in the frame of the wall, the rest of the step streamed.
void Fluid::walls(std::uint64_t step, double dt, Vector3d const &L) {
  WallGeom const g = wall_geom(*this, L);
  for (int i = 0; i < size(); ++i)
    wall_flight(g, step, static_cast<std::uint64_t>(id[i]), dt, pos[i], v[i], momentum_to_wall_lo,
                momentum_to_wall_hi, m_vmax, [](double, Vector3d const &, Vector3d const &) {});
}

int Fluid::move_out(System &s) { return relocate_overlapping(s, 0x5eed0000ull + s.step()); }

void Fluid::md_step(System &s) {
  stream(s, s.time_step());
  ++m_n_streams;
  if (m_n_tau > 0 && m_n_streams % static_cast<std::uint64_t>(m_n_tau) == 0)
    collide(s);
  m_leave_valid = false;
}

} // namespace Marble::Srd
