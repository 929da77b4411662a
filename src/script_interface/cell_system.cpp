// Script interface of the cell system (marble.cell_system): skin, Verlet
// lists, domain decomposition.
#include "script_interface/bindings.hpp"
#include "script_interface/params.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>

namespace ScriptInterface {

using Marble::System;
using Utils::Vector3d;

void bind_cell_system(py::class_<System> &cls) {
  cls.def_property(
      "skin", [](System const &s) { return s.skin(); },
      [](System &s, py::object v) {
        // > 0: a step that moves a particle farther than the skin is refused
        // as a blow-up (integrate.cpp), so a zero skin could never integrate.
        double const skin = check_double("skin", to_double("skin", v), 0., INFINITY, true);
        double const lmin = std::min({s.box().length()[0], s.box().length()[1], s.box().length()[2]});
        if (skin > 0.5 * lmin)
          value_error("parameter 'skin' must be in (0, box_l/2], got " + Utils::to_str(skin));
        s.set_skin(skin);
      });
  cls.def("n_rebuilds", [](System &s) { return s.cells().n_rebuilds(); });
  // 0: rebuild only if a pair may be missing ("pairs"), 1: at half the skin ("half_skin")
  cls.def_property(
      "list_check", [](System const &s) { return static_cast<int>(s.list_check()); },
      [](System &s, int c) { s.set_list_check(c == 0 ? System::ListCheck::Pairs : System::ListCheck::HalfSkin); });
  cls.def("pair_test_applies", &System::pair_test_applies);
  cls.def("node_grid", [](System &s) { return s.cells().node_grid(s.box()); });
  cls.def("local_domain", [](System &s) {
    auto const d = s.cells().local_domain(s.box());
    return std::make_pair(vec_to_array(d.first), vec_to_array(d.second));
  });
  // domain cuts and load balance (system/balance.cpp; checked in marble/cell_system.py)
  cls.def("domain_cuts", [](System &s) {
    std::vector<std::vector<double>> out;
    for (int d = 0; d < 3; ++d)
      out.push_back(s.cells().domain_cuts(s.box(), d));
    return out;
  });
  cls.def("set_domain_cuts", [](System &s, std::vector<std::vector<double>> const &cuts) {
    if (cuts.size() != 3)
      value_error("parameter 'domain_cuts' must have three entries (one per axis)");
    s.set_domain_cuts({cuts[0], cuts[1], cuts[2]});
  });
  cls.def("balance_domains", [](System &s, int by, double damping, double threshold) {
    auto const r = s.balance_domains(static_cast<System::BalanceBy>(by), damping, threshold);
    return std::make_pair(r.imbalance, r.moved);
  });
  cls.def("set_balance", [](System &s, int every, int by, double damping, double threshold) {
    s.set_balance({every, static_cast<System::BalanceBy>(by), damping, threshold});
  });
  cls.def("balance_settings", [](System &s) {
    auto const &b = s.balance_settings();
    return std::make_tuple(b.every, static_cast<int>(b.by), b.damping, b.threshold);
  });
  cls.def("n_balances", &System::n_balances);
  // ids this rank owns (not collective; for tests and diagnostics)
  cls.def("local_ids", [](System &s) { return s.particles().ids_sorted(); });
  cls.def("n_cells", [](System &s) { return s.cells().n_cells(); });
  // this rank's ghosts (periodic images and other ranks' particles; not collective)
  cls.def("n_ghosts", [](System &s) { return s.particles().n_ghost(); });
  // this rank's MPI traffic counters since the last reset (bench/mpi_weak_model.py)
  cls.def("comm_stats", [](System &s) {
    auto const &c = s.comm().stats();
    py::dict d;
    d["allreduce"] = c.allreduce, d["alltoallv"] = c.alltoallv, d["other"] = c.other;
    d["neighbor"] = c.neighbor;
    d["messages"] = c.messages, d["bytes"] = c.bytes;
    d["cpu_seconds"] = c.cpu_seconds, d["wall_seconds"] = c.wall_seconds;
    d["wall_allreduce"] = c.wall_allreduce, d["wall_alltoallv"] = c.wall_alltoallv;
    d["wall_neighbor"] = c.wall_neighbor, d["wall_other"] = c.wall_other;
    return d;
  });
  cls.def("reset_comm_stats", [](System &s) { s.comm().reset_stats(); });
  cls.def("max_cut", &System::max_cutoff);
  // large-range types (cells/CellSystem.hpp): mode -1 auto, 0 off, 1 the given types
  cls.def("set_large_range_mode", [](System &s, int mode, std::vector<int> const &types) {
    std::vector<char> flags;
    for (int t : types) {
      if (t < 0 || t >= Marble::InteractionTable::max_type)
        value_error("parameter 'large_range_types' must hold particle types in [0, " +
                    std::to_string(Marble::InteractionTable::max_type) + "), got " + std::to_string(t));
      if (static_cast<int>(flags.size()) <= t)
        flags.resize(static_cast<std::size_t>(t) + 1, 0);
      flags[static_cast<std::size_t>(t)] = 1;
    }
    s.set_large_range_mode(mode, flags);
  });
  cls.def("large_range_mode", &System::large_range_mode);
  // the types given to set_large_range_mode (mode 1), as a sorted list
  cls.def("large_range_types_requested", [](System &s) {
    std::vector<int> types;
    auto const &w = s.large_range_types_requested();
    for (std::size_t t = 0; t < w.size(); ++t)
      if (w[t])
        types.push_back(static_cast<int>(t));
    return types;
  });
  // the large-range types and ranges (cutoff + skin) of the last list rebuild (not collective)
  cls.def("large_range_state", [](System &s) {
    std::vector<int> types;
    auto const &w = s.cells().large_range_types();
    for (std::size_t t = 0; t < w.size(); ++t)
      if (w[t])
        types.push_back(static_cast<int>(t));
    return py::make_tuple(types, s.cells().range(), s.cells().range_ll(), s.cells().range_ls());
  });
  cls.def("verlet_pairs", [](System &s) {
    s.ensure_lists();
    auto const &ps = s.particles();
    std::vector<std::pair<int, int>> out;
    std::vector<std::array<int, 2>> loc;
    for (auto const &p : s.cells().pairs()) {
      int a = ps.id[p[0]], b = ps.id[p[1]];
      loc.push_back({std::min(a, b), std::max(a, b)});
    }
    for (auto const &p : s.comm().allgatherv(loc)) // every pair is listed on one rank
      out.emplace_back(p[0], p[1]);
    return out;
  });

}

} // namespace ScriptInterface
