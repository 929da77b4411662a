#pragma once
// The process group a System runs on. Every rank runs the same script (SPMD):
// script-interface calls are collective, particle reads gather.
//
// Without MPI (or when MPI was never initialised, e.g. in the C++ unit tests)
// this is a group of one and every call below is a cheap no-op. In an MPI
// build the Python module initialises MPI on import (marble._marble), so a
// plain `build/pymarble script.py` is a one-rank MPI run and
// `mpiexec -n N build/pymarble script.py` an N-rank one.
#include <cstddef>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#ifdef MARBLE_HAVE_MPI
#include <mpi.h>
#endif

namespace Marble {

/** Traffic counters of one Communicator (bench/mpi_weak_model.py; not collective). */
struct CommStats {
  long long allreduce = 0;  ///< reductions (sum/max/min) on more than one rank
  long long alltoallv = 0;  ///< alltoallv exchanges (each: one MPI_Alltoall of counts + one MPI_Alltoallv)
  long long neighbor = 0;   ///< neighbour exchanges (point-to-point: fixed sizes, or sizes probed)
  long long other = 0;      ///< broadcasts, allgathers, barriers
  long long messages = 0;   ///< messages sent to other ranks (non-empty alltoallv blocks, neighbour messages)
  long long bytes = 0;      ///< bytes of those blocks
  double cpu_seconds = 0.;  ///< this thread's CPU time inside those MPI calls (waits poll: CPU)
  double wall_seconds = 0.; ///< wall time inside those MPI calls
  /// that wall time by kind (where a rank waits: the reductions' votes or the exchanges)
  double wall_allreduce = 0., wall_alltoallv = 0., wall_neighbor = 0., wall_other = 0.;
};

class Communicator {
public:
  /** MPI_COMM_WORLD if MPI is initialised, else a group of one. */
  Communicator();

  int rank() const { return m_rank; }
  int size() const { return m_size; }
  bool is_root() const { return m_rank == 0; }
  bool parallel() const { return m_size > 1; }
#ifdef MARBLE_HAVE_MPI
  /** The MPI communicator (MPI_COMM_SELF when MPI is not initialised). */
  MPI_Comm comm() const { return m_comm; }
#endif

  // --- reductions (result on every rank) ---
  void sum_inplace(double *x, int n) const;
  void sum_inplace(long long *x, int n) const;
  double sum(double x) const {
    sum_inplace(&x, 1);
    return x;
  }
  long long sum(long long x) const {
    sum_inplace(&x, 1);
    return x;
  }
  double max(double x) const;
  /** Elementwise maximum of @p n values over the ranks, in place. */
  void max_inplace(double *x, int n) const;
  double min(double x) const;
  int max(int x) const;
  int min(int x) const;
  bool any(bool b) const { return max(b ? 1 : 0) > 0; }

  // --- data movement (T trivially copyable) ---
  /** Broadcast raw bytes from @p root (the size must be equal on all ranks). */
  void bcast_bytes(void *data, std::size_t n, int root) const;
  /** Broadcast a byte vector of any size from @p root. */
  void bcast(std::vector<char> &data, int root) const;
  void bcast(std::string &s, int root) const;
  template <typename T> void bcast_value(T &x, int root) const {
    static_assert(std::is_trivially_copyable_v<T>);
    bcast_bytes(&x, sizeof(T), root);
  }
  /** Concatenation of every rank's @p local in rank order, on every rank. */
  template <typename T> std::vector<T> allgatherv(std::vector<T> const &local) const {
    static_assert(std::is_trivially_copyable_v<T>);
    std::vector<char> bytes(local.size() * sizeof(T));
    if (!local.empty())
      std::memcpy(bytes.data(), local.data(), bytes.size());
    auto const all = allgatherv_bytes(bytes);
    std::vector<T> out(all.size() / sizeof(T));
    if (!out.empty())
      std::memcpy(out.data(), all.data(), all.size());
    return out;
  }
  /** Per-rank counts of allgatherv (bytes / sizeof(T)). */
  std::vector<int> allgather(int x) const;
  /** @p send[r] goes to rank r; returns what every rank sent to this one, by source rank. */
  template <typename T>
  std::vector<std::vector<T>> alltoallv(std::vector<std::vector<T>> const &send) const {
    static_assert(std::is_trivially_copyable_v<T>);
    std::vector<std::vector<char>> sb(send.size());
    for (std::size_t r = 0; r < send.size(); ++r) {
      sb[r].resize(send[r].size() * sizeof(T));
      if (!send[r].empty())
        std::memcpy(sb[r].data(), send[r].data(), sb[r].size());
    }
    auto const rb = alltoallv_bytes(sb);
    std::vector<std::vector<T>> out(rb.size());
    for (std::size_t r = 0; r < rb.size(); ++r) {
      out[r].resize(rb[r].size() / sizeof(T));
      if (!out[r].empty())
        std::memcpy(out[r].data(), rb[r].data(), rb[r].size());
    }
    return out;
  }
  /** Neighbour exchange with sizes known on both sides (no count exchange):
   * @p send[r] goes to rank r and @p recv[r], which the caller has sized to
   * what rank r sends, is filled from rank r; only non-empty blocks become
   * messages (MPI_Isend/MPI_Irecv), so only the ranks that exchange data take
   * part. Every rank of the group must call it (an empty call is free). */
  void neighbor_exchange_bytes(std::vector<std::vector<char>> const &send,
                               std::vector<std::vector<char>> &recv) const;
  /** One block of a neighbour exchange: @p bytes at @p data to or from @p rank. */
  struct Block {
    int rank;
    void *data;
    std::size_t bytes;
  };
  /** neighbor_exchange_bytes on caller-owned memory (no buffer copies or
   * resizes here): the @p n_send blocks of @p send go out, the @p n_recv
   * blocks of @p recv are filled; both sides must agree on the sizes and,
   * for several blocks between two ranks, on their order. Empty blocks and
   * blocks for this rank are skipped. Every rank of the group must call it. */
  void neighbor_exchange_blocks(Block const *send, int n_send, Block const *recv, int n_recv) const;
  /** Neighbour exchange of blocks of any size with the ranks @p nbrs (which
   * must be symmetric: q lists this rank iff this rank lists q): @p send[q]
   * goes to each q of @p nbrs (one message each, also when empty) and
   * @p recv[q] is resized and filled from each; the sizes travel with the
   * messages (MPI_Probe), so there is no count exchange and no all-rank call.
   * Every rank of the group must call it. */
  void neighbor_exchange_var_bytes(std::vector<int> const &nbrs,
                                   std::vector<std::vector<char>> const &send,
                                   std::vector<std::vector<char>> &recv) const;
  /** Typed form of neighbor_exchange_var_bytes: returns the blocks by source rank. */
  template <typename T>
  std::vector<std::vector<T>> neighbor_exchange_var(std::vector<int> const &nbrs,
                                                    std::vector<std::vector<T>> const &send) const {
    static_assert(std::is_trivially_copyable_v<T>);
    std::vector<std::vector<char>> sb(send.size()), rb(send.size());
    for (int q : nbrs) {
      auto const &b = send[static_cast<std::size_t>(q)];
      sb[q].resize(b.size() * sizeof(T));
      if (!b.empty())
        std::memcpy(sb[q].data(), b.data(), sb[q].size());
    }
    neighbor_exchange_var_bytes(nbrs, sb, rb);
    std::vector<std::vector<T>> out(send.size());
    for (int q : nbrs) {
      out[q].resize(rb[q].size() / sizeof(T));
      if (!out[q].empty())
        std::memcpy(out[q].data(), rb[q].data(), out[q].size() * sizeof(T));
    }
    return out;
  }
  std::vector<char> allgatherv_bytes(std::vector<char> const &local) const;
  std::vector<std::vector<char>> alltoallv_bytes(std::vector<std::vector<char>> const &send) const;
  void barrier() const;

  /** Collective error check: if any rank passes a non-empty @p local_error,
   * every rank throws Utils::RuntimeError with the message of the lowest such
   * rank (so no rank is left waiting in a collective call). */
  void throw_if_any(std::string const &local_error) const;

  /** Counters of the collective calls and alltoallv traffic since the last reset. */
  CommStats const &stats() const { return m_stats; }
  void reset_stats() const { m_stats = {}; }

private:
  int m_rank = 0, m_size = 1;
  mutable CommStats m_stats;
#ifdef MARBLE_HAVE_MPI
  MPI_Comm m_comm = MPI_COMM_SELF;
#endif
};

/** Initialise MPI if the build has it and nobody did yet (idempotent). */
void mpi_init_once();
/** Finalise MPI if this module initialised it. */
void mpi_finalize_once();
/** Stop all ranks (MPI_Abort; std::exit without MPI). */
[[noreturn]] void mpi_abort(int code);

} // namespace Marble
