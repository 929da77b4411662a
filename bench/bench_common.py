"""Shared by the benches: the machine record every result file carries."""
import os
import platform
import re
import subprocess
import time

import marble

HERE = os.path.dirname(os.path.abspath(__file__))


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
