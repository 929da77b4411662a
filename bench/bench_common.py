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
