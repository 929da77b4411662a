"""Shared by the benches: the machine record every result file carries."""
import json
import os
import platform
import re
import subprocess
import sys
import time

import marble

HERE = os.path.dirname(os.path.abspath(__file__))


# The probe's child: a small DPD fluid (the benches' kind of work: the pair
# loop, the Verlet rebuild, memory-bound sweeps), pinned to one core, timed by
# its own CPU clock; the best of several repeats (a repeat hit by another
# process only gets slower).
_PROBE = r"""
import json, os, sys, time
os.sched_setaffinity(0, {int(sys.argv[1])})
import numpy as np
import marble
rng = np.random.default_rng(1)
L = 12.0
s = marble.System(box_l=[L] * 3)
s.time_step = 0.01
s.cell_system.skin = 0.4
s.part.add(pos=rng.uniform(0, L, (int(3 * L**3), 3)), v=rng.normal(size=(int(3 * L**3), 3)))
s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0)
s.thermostat.set_dpd(kT=1.0, seed=3)
s.integrator.run(20)
best = float("inf")
for _ in range(int(sys.argv[2])):
    t = time.process_time()
    s.integrator.run(100)
    best = min(best, time.process_time() - t)
print(json.dumps(dict(rate=len(s.part.all().id) * 100 / best)))
"""


def core_speeds(repeats=7):
    """Each core's speed for the benches' kind of work: particle-steps per
    CPU-second of a small DPD fluid (5184 beads, best of @p repeats x 100
    steps) pinned to that core, the cores probed one after another. A
    virtual machine's cores can differ for minutes at a time with no steal
    time reported (doc/parallel.md, session 27), which no load test sees:
    ``spread`` (slowest / fastest - 1) says so. Returns None where the
    affinity cannot be set (not Linux) or the probe fails."""
    if not hasattr(os, "sched_getaffinity"):
        return None
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    rates = {}
    for cpu in sorted(os.sched_getaffinity(0)):
        try:
            r = subprocess.run([sys.executable, "-c", _PROBE, str(cpu), str(repeats)], env=env,
                               capture_output=True, text=True, timeout=300)
            rates[cpu] = json.loads(r.stdout.strip().splitlines()[-1])["rate"]
        except (OSError, subprocess.SubprocessError, ValueError, IndexError, KeyError):
            return None
    fast, slow = max(rates.values()), min(rates.values())
    return dict(rates={str(c): v for c, v in rates.items()}, spread=fast / slow - 1.0)


def core_speeds_line(cs):
    """One line for a bench's output: each core's rate and the spread."""
    if cs is None:
        return "core speeds: not measured"
    rates = ", ".join(f"core {c} {v:.3g}" for c, v in cs["rates"].items())
    warn = " (the cores differ: per-rank and one-core figures of this run mix their speeds)" \
        if cs["spread"] > 0.10 else ""
    return f"core speeds (particle-steps per CPU-second of a 5184-bead DPD fluid): {rates}; " \
           f"slowest {100 * cs['spread']:.1f} % below the fastest{warn}"


def probe_cores(when=""):
    """core_speeds(), printed as core_speeds_line (tagged "(@p when)" if
    given): what the speed benches record before and after their runs."""
    cs = core_speeds()
    print(core_speeds_line(cs) + (f" ({when})" if when else ""), flush=True)
    return cs


def machine_info():
    """CPU model, cores, load average, Python, git revision, features, build options, date."""
    cpu = platform.processor()
    try:
        with open("/proc/cpuinfo") as f:
            m = re.search(r"model name\s*:\s*(.*)", f.read())
            cpu = m.group(1) if m else cpu
    except OSError:
        pass
    try:
        rev = subprocess.run(["git", "-C", HERE, "rev-parse", "--short", "HEAD"],
                             capture_output=True, text=True).stdout.strip()
    except OSError:
        rev = ""
    return dict(cpu=cpu, cores=os.cpu_count(), load_avg=list(os.getloadavg()),
                python=platform.python_version(), marble_git=rev,
                features=sorted(marble.features()), build_options=marble.build_options(),
                date=time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()))


def lj_fcc_system(ncell, rng):
    """LAMMPS's in.lj scene: an fcc lattice of 4 ncell^3 atoms at rho = 0.8442,
    velocities drawn from @p rng at T = 1.44 (zero total momentum), LJ with
    cutoff 2.5, dt = 0.005, skin 0.3 (not yet run)."""
    import numpy as np
    rho = 0.8442
    a = (4.0 / rho) ** (1.0 / 3.0)
    basis = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
    g = np.arange(ncell)
    cells = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T
    pos = (cells[:, None, :] + basis[None, :, :]).reshape(-1, 3) * a
    s = marble.System(box_l=[ncell * a] * 3)
    s.time_step = 0.005
    s.cell_system.skin = 0.3
    v = rng.normal(size=pos.shape) * np.sqrt(1.44)
    s.part.add(pos=pos, v=v - v.mean(axis=0))
    s.non_bonded_inter[0, 0].lennard_jones.set_params(epsilon=1.0, sigma=1.0, cutoff=2.5, shift=0.0)
    return s
