#include "comm/Communicator.hpp"

#include "utils/errors.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <thread>
#include <time.h>

namespace Marble {

#ifdef MARBLE_HAVE_MPI
namespace {
bool g_we_initialised = false;
// A duplicate of MPI_COMM_WORLD used only for the exit handshake below (so it
// never matches a collective call of marble on MPI_COMM_WORLD).
MPI_Comm g_exit_comm = MPI_COMM_NULL;
bool mpi_ready() {
  int init = 0, fin = 0;
  MPI_Initialized(&init);
  MPI_Finalized(&fin);
  return init && !fin;
}
} // namespace

void mpi_init_once() {
  int init = 0;
  MPI_Initialized(&init);
  if (!init) {
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    g_we_initialised = true;
    MPI_Comm_dup(MPI_COMM_WORLD, &g_exit_comm);
  }
}

namespace {
/** Exit handshake: a rank that reached the end of the script waits (on its
 * own communicator, polling) until every rank has. If some rank is still
 * inside a collective marble call after 10 s, the usual cause is a call made
 * on some ranks only (a particle read inside `if marble.mpi_rank() == 0:`),
 * which would otherwise hang in MPI_Finalize without a word: say so on
 * stderr, and after MARBLE_MPI_EXIT_TIMEOUT seconds (default 600; 0: wait
 * forever) stop all ranks with MPI_Abort. */
void exit_handshake() {
  int size = 1, rank = 0;
  MPI_Comm_size(g_exit_comm, &size);
  MPI_Comm_rank(g_exit_comm, &rank);
  if (size == 1)
    return;
  double timeout = 600.;
  if (char const *e = std::getenv("MARBLE_MPI_EXIT_TIMEOUT")) {
    char *end = nullptr;
    double const t = std::strtod(e, &end);
    if (end != e && t >= 0.)
      timeout = t;
  }
  double const warn_after = timeout > 0. ? std::min(10., 0.5 * timeout) : 10.;
  MPI_Request req;
  MPI_Ibarrier(g_exit_comm, &req);
  auto const t0 = std::chrono::steady_clock::now();
  bool warned = false;
  for (;;) {
    int done = 0;
    MPI_Test(&req, &done, MPI_STATUS_IGNORE);
    if (done)
      return;
    double const waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!warned && waited >= warn_after) {
      warned = true;
      std::fprintf(stderr,
                   "marble: rank %d reached the end of the script %.0f s ago, but another rank "
                   "has not: it is probably waiting in a collective marble call that this rank "
                   "never made (a particle read such as p.pos, an observable or analysis call "
                   "inside `if marble.mpi_rank() == 0:`; do the reads on every rank, then write "
                   "on rank 0 only: doc/parallel.md)%s\n",
                   rank, waited,
                   timeout > 0. ? "; all ranks stop after MARBLE_MPI_EXIT_TIMEOUT seconds" : "");
      std::fflush(stderr);
    }
    if (timeout > 0. && waited >= timeout) {
      std::fprintf(stderr,
                   "marble: rank %d stops all ranks: the other ranks did not reach the end of the "
                   "script within MARBLE_MPI_EXIT_TIMEOUT = %g s (see the message above)\n",
                   rank, timeout);
      std::fflush(stderr);
      MPI_Abort(MPI_COMM_WORLD, 1);
    }
    if (waited < 1.)
      std::this_thread::yield();
    else
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}
} // namespace

void mpi_finalize_once() {
  if (g_we_initialised && mpi_ready()) {
    if (g_exit_comm != MPI_COMM_NULL) {
      exit_handshake();
      MPI_Comm_free(&g_exit_comm);
    }
    MPI_Finalize();
  }
  g_we_initialised = false;
}

void mpi_abort(int code) {
  if (mpi_ready())
    MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

Communicator::Communicator() {
  if (mpi_ready()) {
    m_comm = MPI_COMM_WORLD;
    MPI_Comm_rank(m_comm, &m_rank);
    MPI_Comm_size(m_comm, &m_size);
  }
}

namespace {
/** Adds the thread CPU time and the wall time of its scope to the counters
 * (bench/mpi_scaling.py: the time a rank spends in communication and waits). */
class CommTimer {
public:
  /** @p kind: the CommStats member that gets the wall time by kind too. */
  CommTimer(CommStats &s, double CommStats::*kind) : m_s(s), m_kind(kind), m_c0(cpu_now()), m_w0(MPI_Wtime()) {}
  ~CommTimer() {
    double const w = MPI_Wtime() - m_w0;
    m_s.cpu_seconds += cpu_now() - m_c0;
    m_s.wall_seconds += w;
    m_s.*m_kind += w;
  }
  CommTimer(CommTimer const &) = delete;
  CommTimer &operator=(CommTimer const &) = delete;

private:
  static double cpu_now() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  }
  CommStats &m_s;
  double CommStats::*m_kind;
  double m_c0, m_w0;
};

template <typename T> MPI_Datatype mpi_type();
template <> MPI_Datatype mpi_type<double>() { return MPI_DOUBLE; }
template <> MPI_Datatype mpi_type<long long>() { return MPI_LONG_LONG; }
template <> MPI_Datatype mpi_type<int>() { return MPI_INT; }

// In-place allreduce of n values (nothing to do on one rank).
template <typename T> void allreduce(CommStats &st, MPI_Comm comm, int size, T *x, int n, MPI_Op op) {
  if (size > 1 && n > 0) {
    ++st.allreduce;
    CommTimer const timer(st, &CommStats::wall_allreduce);
    MPI_Allreduce(MPI_IN_PLACE, x, n, mpi_type<T>(), op, comm);
  }
}
} // namespace

void Communicator::sum_inplace(double *x, int n) const { allreduce(m_stats, m_comm, m_size, x, n, MPI_SUM); }
void Communicator::sum_inplace(long long *x, int n) const { allreduce(m_stats, m_comm, m_size, x, n, MPI_SUM); }
double Communicator::max(double x) const {
  allreduce(m_stats, m_comm, m_size, &x, 1, MPI_MAX);
  return x;
}
void Communicator::max_inplace(double *x, int n) const { allreduce(m_stats, m_comm, m_size, x, n, MPI_MAX); }
double Communicator::min(double x) const {
  allreduce(m_stats, m_comm, m_size, &x, 1, MPI_MIN);
  return x;
}
int Communicator::max(int x) const {
  allreduce(m_stats, m_comm, m_size, &x, 1, MPI_MAX);
  return x;
}
int Communicator::min(int x) const {
  allreduce(m_stats, m_comm, m_size, &x, 1, MPI_MIN);
  return x;
}
void Communicator::bcast_bytes(void *data, std::size_t n, int root) const {
  if (m_size > 1 && n > 0) {
    ++m_stats.other;
    CommTimer const timer(m_stats, &CommStats::wall_other);
    MPI_Bcast(data, static_cast<int>(n), MPI_BYTE, root, m_comm);
  }
}
void Communicator::bcast(std::vector<char> &data, int root) const {
  if (m_size == 1)
    return;
  long long n = static_cast<long long>(data.size());
  MPI_Bcast(&n, 1, MPI_LONG_LONG, root, m_comm);
  data.resize(static_cast<std::size_t>(n));
  bcast_bytes(data.data(), data.size(), root);
}
void Communicator::bcast(std::string &s, int root) const {
  if (m_size == 1)
    return;
  std::vector<char> v(s.begin(), s.end());
  bcast(v, root);
  s.assign(v.begin(), v.end());
}
std::vector<int> Communicator::allgather(int x) const {
  std::vector<int> out(m_size, x);
  if (m_size > 1) {
    ++m_stats.other;
    CommTimer const timer(m_stats, &CommStats::wall_other);
    MPI_Allgather(&x, 1, MPI_INT, out.data(), 1, MPI_INT, m_comm);
  }
  return out;
}
std::vector<char> Communicator::allgatherv_bytes(std::vector<char> const &local) const {
  if (m_size == 1)
    return local;
  auto const counts = allgather(static_cast<int>(local.size()));
  std::vector<int> displs(m_size, 0);
  for (int r = 1; r < m_size; ++r)
    displs[r] = displs[r - 1] + counts[r - 1];
  std::vector<char> out(static_cast<std::size_t>(displs.back() + counts.back()));
  CommTimer const timer(m_stats, &CommStats::wall_other);
  MPI_Allgatherv(local.data(), static_cast<int>(local.size()), MPI_BYTE, out.data(), counts.data(),
                 displs.data(), MPI_BYTE, m_comm);
  return out;
}
std::vector<std::vector<char>>
Communicator::alltoallv_bytes(std::vector<std::vector<char>> const &send) const {
  if (m_size == 1)
    return {send.empty() ? std::vector<char>{} : send[0]};
  std::vector<int> sc(m_size, 0), rc(m_size, 0), sd(m_size, 0), rd(m_size, 0);
  ++m_stats.alltoallv;
  CommTimer const timer(m_stats, &CommStats::wall_alltoallv);
  for (int r = 0; r < m_size && r < static_cast<int>(send.size()); ++r) {
    sc[r] = static_cast<int>(send[r].size());
    if (r != m_rank && sc[r] > 0) {
      ++m_stats.messages;
      m_stats.bytes += sc[r];
    }
  }
  MPI_Alltoall(sc.data(), 1, MPI_INT, rc.data(), 1, MPI_INT, m_comm);
  for (int r = 1; r < m_size; ++r) {
    sd[r] = sd[r - 1] + sc[r - 1];
    rd[r] = rd[r - 1] + rc[r - 1];
  }
  std::vector<char> sbuf(static_cast<std::size_t>(sd.back() + sc.back()));
  for (int r = 0; r < m_size && r < static_cast<int>(send.size()); ++r)
    std::copy(send[r].begin(), send[r].end(), sbuf.begin() + sd[r]);
  std::vector<char> rbuf(static_cast<std::size_t>(rd.back() + rc.back()));
  MPI_Alltoallv(sbuf.data(), sc.data(), sd.data(), MPI_BYTE, rbuf.data(), rc.data(), rd.data(),
                MPI_BYTE, m_comm);
  std::vector<std::vector<char>> out(m_size);
  for (int r = 0; r < m_size; ++r)
    out[r].assign(rbuf.begin() + rd[r], rbuf.begin() + rd[r] + rc[r]);
  return out;
}
void Communicator::neighbor_exchange_bytes(std::vector<std::vector<char>> const &send,
                                           std::vector<std::vector<char>> &recv) const {
  if (m_size == 1)
    return;
  std::vector<Block> sb, rb;
  for (int r = 0; r < m_size && r < static_cast<int>(recv.size()); ++r)
    rb.push_back({r, recv[r].data(), recv[r].size()});
  for (int r = 0; r < m_size && r < static_cast<int>(send.size()); ++r)
    sb.push_back({r, const_cast<char *>(send[r].data()), send[r].size()});
  neighbor_exchange_blocks(sb.data(), static_cast<int>(sb.size()), rb.data(), static_cast<int>(rb.size()));
}
void Communicator::neighbor_exchange_blocks(Block const *send, int n_send, Block const *recv,
                                            int n_recv) const {
  if (m_size == 1)
    return;
  ++m_stats.neighbor;
  CommTimer const timer(m_stats, &CommStats::wall_neighbor);
  // one tag for all: the blocks between two ranks arrive in the order sent
  // (MPI's non-overtaking rule), and each call completes before the next
  constexpr int kTag = 7301;
  thread_local std::vector<MPI_Request> req;
  req.clear();
  for (int k = 0; k < n_recv; ++k)
    if (recv[k].rank != m_rank && recv[k].bytes > 0) {
      req.emplace_back();
      MPI_Irecv(recv[k].data, static_cast<int>(recv[k].bytes), MPI_BYTE, recv[k].rank, kTag, m_comm,
                &req.back());
    }
  for (int k = 0; k < n_send; ++k)
    if (send[k].rank != m_rank && send[k].bytes > 0) {
      ++m_stats.messages;
      m_stats.bytes += static_cast<long long>(send[k].bytes);
      req.emplace_back();
      MPI_Isend(send[k].data, static_cast<int>(send[k].bytes), MPI_BYTE, send[k].rank, kTag, m_comm,
                &req.back());
    }
  if (!req.empty())
    MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
}
void Communicator::neighbor_exchange_var_bytes(std::vector<int> const &nbrs,
                                               std::vector<std::vector<char>> const &send,
                                               std::vector<std::vector<char>> &recv) const {
  if (m_size == 1)
    return;
  ++m_stats.neighbor;
  CommTimer const timer(m_stats, &CommStats::wall_neighbor);
  // its own tag: never matched by the fixed-size exchange's receives; blocks
  // between two ranks arrive in the order sent (non-overtaking)
  constexpr int kTag = 7302;
  recv.resize(static_cast<std::size_t>(m_size));
  std::vector<MPI_Request> req(nbrs.size());
  for (std::size_t k = 0; k < nbrs.size(); ++k) {
    int const q = nbrs[k];
    auto const &b = send[static_cast<std::size_t>(q)];
    ++m_stats.messages;
    m_stats.bytes += static_cast<long long>(b.size());
    MPI_Isend(b.data(), static_cast<int>(b.size()), MPI_BYTE, q, kTag, m_comm, &req[k]);
  }
  for (int q : nbrs) {
    MPI_Status st;
    MPI_Probe(q, kTag, m_comm, &st);
    int n = 0;
    MPI_Get_count(&st, MPI_BYTE, &n);
    auto &b = recv[static_cast<std::size_t>(q)];
    b.resize(static_cast<std::size_t>(n));
    MPI_Recv(b.data(), n, MPI_BYTE, q, kTag, m_comm, MPI_STATUS_IGNORE);
  }
  if (!req.empty())
    MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
}
void Communicator::barrier() const {
  if (m_size > 1) {
    ++m_stats.other;
    CommTimer const timer(m_stats, &CommStats::wall_other);
    MPI_Barrier(m_comm);
  }
}
void Communicator::throw_if_any(std::string const &local_error) const {
  if (m_size == 1) {
    if (!local_error.empty())
      throw Utils::RuntimeError(local_error);
    return;
  }
  int const first = min(local_error.empty() ? m_size : m_rank);
  if (first == m_size)
    return;
  std::string msg = local_error;
  bcast(msg, first);
  throw Utils::RuntimeError(msg);
}

#else // no MPI

void mpi_init_once() {}
void mpi_finalize_once() {}
void mpi_abort(int code) { std::exit(code); }
Communicator::Communicator() = default;
void Communicator::sum_inplace(double *, int) const {}
void Communicator::sum_inplace(long long *, int) const {}
double Communicator::max(double x) const { return x; }
void Communicator::max_inplace(double *, int) const {}
double Communicator::min(double x) const { return x; }
int Communicator::max(int x) const { return x; }
int Communicator::min(int x) const { return x; }
void Communicator::bcast_bytes(void *, std::size_t, int) const {}
void Communicator::bcast(std::vector<char> &, int) const {}
void Communicator::bcast(std::string &, int) const {}
std::vector<int> Communicator::allgather(int x) const { return {x}; }
std::vector<char> Communicator::allgatherv_bytes(std::vector<char> const &local) const { return local; }
std::vector<std::vector<char>>
Communicator::alltoallv_bytes(std::vector<std::vector<char>> const &send) const {
  return {send.empty() ? std::vector<char>{} : send[0]};
}
void Communicator::neighbor_exchange_bytes(std::vector<std::vector<char>> const &,
                                           std::vector<std::vector<char>> &) const {}
void Communicator::neighbor_exchange_blocks(Block const *, int, Block const *, int) const {}
void Communicator::neighbor_exchange_var_bytes(std::vector<int> const &,
                                               std::vector<std::vector<char>> const &,
                                               std::vector<std::vector<char>> &) const {}
void Communicator::barrier() const {}
void Communicator::throw_if_any(std::string const &local_error) const {
  if (!local_error.empty())
    throw Utils::RuntimeError(local_error);
}
#endif

} // namespace Marble
