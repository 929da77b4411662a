# labels: python mpi
"""Faults (doc/reliability.md):

- kill -9 of a process that saves checkpoints in a loop, at random moments
  (fixed seed), leaves every complete checkpoint file loadable and the last
  one equal to what was saved (atomic writes, doc/io.md);
- a rank dying under ``mpiexec -n 2`` (SIGKILL during a run, os._exit between
  calls) ends the job with a message and a non-zero exit status, not a hang
  (each run has a timeout);
- a full disk (emulated with RLIMIT_FSIZE, which applies to root too), a path
  below a regular file, a read-only directory (as non-root) and /dev/full give
  a clear error for checkpoint save and H5MD, and the previous checkpoint stays.
"""
import os
import re
import shutil
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import marble
import marble.checkpointing
import marble.io

MPIEXEC = shutil.which("mpiexec")
SANITIZE = os.environ.get("MARBLE_SANITIZE") == "1"
SLOW = 4.0 if SANITIZE else 1.0  # start-up and run times under ASan


def mpi_env(**extra):
    return dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                OMPI_MCA_rmaps_base_oversubscribe="1", **extra)


# --- kill -9 while saving ------------------------------------------------------------------

SAVER = textwrap.dedent("""
    import sys
    import numpy as np
    import marble, marble.checkpointing
    path = sys.argv[1]
    system = marble.System(box_l=[12.0] * 3)
    system.time_step = 0.01
    system.cell_system.skin = 0.4
    rng = np.random.default_rng(1)
    system.part.add(pos=rng.random((3000, 3)) * 12.0, v=rng.normal(size=(3000, 3)))
    cp = marble.checkpointing.Checkpoint(checkpoint_id="loop", checkpoint_path=path,
                                         namespace={"system": system})
    cp.register("system")
    cp.save(0)
    print("READY", flush=True)
    k = 0
    while True:
        k += 1
        system.time = float(k)      # the file's identity: time == index of the save
        cp.save(k % 4)              # overwrite 4 files in rotation
        with open(path + "/last_done", "w") as f:   # the save returned
            f.write(str(k))
""")


def test_kill_9_during_checkpoint_writes(tmp_path):
    script = tmp_path / "saver.py"
    script.write_text(SAVER)
    rng = np.random.default_rng(2026)
    n_tmp_left = 0
    for trial in range(5):
        d = tmp_path / f"trial{trial}"
        d.mkdir()
        p = subprocess.Popen([sys.executable, str(script), str(d)], stdout=subprocess.PIPE,
                             text=True, env=dict(os.environ))
        try:
            assert p.stdout.readline().strip() == "READY"
            time.sleep(float(rng.uniform(0.05, 0.6)) * SLOW)
            p.send_signal(signal.SIGKILL)
            assert p.wait(timeout=60) == -signal.SIGKILL
        finally:
            if p.poll() is None:
                p.kill()
                p.wait()
        files = sorted((d / "loop").iterdir())
        n_tmp_left += sum(f.name.endswith(".tmp") for f in files)
        last_done = int((d / "last_done").read_text() or 0) if (d / "last_done").exists() else 0
        # every complete file loads, and holds what was saved under its index
        times = {}
        for f in files:
            if not f.name.endswith(".checkpoint"):
                continue
            idx = int(f.name.split(".")[0])
            ns = {}
            cp = marble.checkpointing.Checkpoint(checkpoint_id="loop", checkpoint_path=str(d),
                                                 namespace=ns)
            cp.load(idx)
            s = ns["system"]
            assert len(s.part) == 3000
            t = int(round(s.time))
            assert t % 4 == idx or (t == 0 and idx == 0), (f.name, t)
            times[idx] = t
            del ns, s
        # the save that returned last is on disk (or a newer one in its slot)
        if last_done:
            assert times[last_done % 4] >= last_done, (times, last_done)
        # and load() of the last index ignores stray temporary files
        ns = {}
        marble.checkpointing.Checkpoint(checkpoint_id="loop", checkpoint_path=str(d),
                                        namespace=ns).load()
        assert len(ns["system"].part) == 3000
    print(f"kill -9: {n_tmp_left} temporary file(s) left by kills during a write")


# --- full disk and unwritable paths --------------------------------------------------------

FSIZE = textwrap.dedent("""
    import resource, signal, sys
    import numpy as np
    import marble, marble.checkpointing, marble.io
    path, what = sys.argv[1], sys.argv[2]
    system = marble.System(box_l=[10.0] * 3)
    system.time_step = 0.01
    system.part.add(pos=np.random.default_rng(0).random((10, 3)) * 10)
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)   # writes past the limit fail with EFBIG
    if what == "checkpoint":
        ns = {"system": system}
        cp = marble.checkpointing.Checkpoint(checkpoint_id="full", checkpoint_path=path,
                                             namespace=ns)
        cp.register("system")
        cp.save(0)                                  # small: fits
        resource.setrlimit(resource.RLIMIT_FSIZE, (65536, 65536))
        system.part.add(pos=np.random.default_rng(1).random((5000, 3)) * 10)
        try:
            cp.save(0)
        except RuntimeError as e:
            print("ERROR:", e)
        else:
            print("NO ERROR")
    else:
        resource.setrlimit(resource.RLIMIT_FSIZE, (65536, 65536))
        system.part.add(pos=np.random.default_rng(1).random((2000, 3)) * 10)
        try:
            h5 = marble.io.H5md(file_path=path + "/traj.h5", system=system)
            for _ in range(50):
                h5.write()
            h5.close()
        except RuntimeError as e:
            print("ERROR:", e)
        else:
            print("NO ERROR")
        system.integrator.run(1)                    # still usable
        print("USABLE")
""")


def run_fsize(tmp_path, what):
    script = tmp_path / "fsize.py"
    script.write_text(FSIZE)
    p = subprocess.run([sys.executable, str(script), str(tmp_path), what], capture_output=True,
                       text=True, timeout=300, env=dict(os.environ))
    return p


def test_checkpoint_full_disk_keeps_previous(tmp_path):
    p = run_fsize(tmp_path, "checkpoint")
    out = p.stdout
    assert p.returncode == 0, out + p.stderr
    assert "ERROR:" in out, out
    msg = out.split("ERROR:", 1)[1]
    assert "0.checkpoint" in msg and "File too large" in msg, msg
    files = os.listdir(tmp_path / "full")
    assert files == ["0.checkpoint"], files  # no temporary file left
    ns = {}
    marble.checkpointing.Checkpoint(checkpoint_id="full", checkpoint_path=str(tmp_path),
                                    namespace=ns).load(0)
    assert len(ns["system"].part) == 10  # the previous checkpoint, intact


@pytest.mark.skipif(not marble.io.have_hdf5(), reason="built without HDF5")
def test_h5md_full_disk(tmp_path):
    p = run_fsize(tmp_path, "h5md")
    out = p.stdout
    assert "ERROR:" in out, out + p.stderr
    msg = out.split("ERROR:", 1)[1].strip().splitlines()[0]
    assert "traj.h5" in msg and "H5MD" in msg and "disk full" in msg, msg
    assert "USABLE" in out
    if p.returncode != 0 and "H5F__close_cb" in p.stderr:  # SIGSEGV, or ASan's report
        pytest.xfail("known HDF5 1.10.8 bug (Debian 12): after an H5Fclose that failed on a "
                     "full disk, HDF5's own termination at MPI_Finalize dereferences the "
                     "half-closed file and the process segfaults at exit; the error itself "
                     "was reported cleanly and the run continued")
    assert p.returncode == 0, out + p.stderr


DEV_FULL = textwrap.dedent("""
    import numpy as np
    import marble, marble.io
    system = marble.System(box_l=[10.0] * 3)
    system.part.add(pos=np.random.default_rng(0).random((500, 3)) * 10)
    for mode in ("w", "append"):
        try:
            marble.io.H5md(file_path="/dev/full", system=system, mode=mode)
        except RuntimeError as e:
            print("ERROR:", e)
""")


@pytest.mark.skipif(not marble.io.have_hdf5(), reason="built without HDF5")
def test_h5md_dev_full(tmp_path):
    # in a subprocess: the process must also exit cleanly (a failed H5Fcreate
    # on a device used to leave HDF5 with a half-open file that crashed at exit)
    script = tmp_path / "devfull.py"
    script.write_text(DEV_FULL)
    p = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                       timeout=300, env=dict(os.environ))
    assert p.returncode == 0, p.stdout + p.stderr
    errors = [ln for ln in p.stdout.splitlines() if ln.startswith("ERROR:")]
    assert len(errors) == 2, p.stdout
    for e in errors:
        assert "'/dev/full': not a regular file" in e, e


def test_checkpoint_path_below_a_file(tmp_path):
    (tmp_path / "afile").write_text("x")
    with pytest.raises(RuntimeError, match="cannot create the checkpoint directory .*afile"):
        marble.checkpointing.Checkpoint(checkpoint_id="c", checkpoint_path=str(tmp_path / "afile"))


@pytest.mark.skipif(not marble.io.have_hdf5(), reason="built without HDF5")
def test_h5md_path_below_a_file(tmp_path):
    (tmp_path / "afile").write_text("x")
    system = marble.System(box_l=[10.0] * 3)
    with pytest.raises(RuntimeError, match="cannot create file .*afile/traj.h5"):
        marble.io.H5md(file_path=str(tmp_path / "afile" / "traj.h5"), system=system)


@pytest.mark.skipif(os.geteuid() == 0, reason="root ignores directory permissions "
                    "(the full-disk and path-below-a-file tests cover root)")
def test_read_only_directory(tmp_path):
    system = marble.System(box_l=[10.0] * 3)
    system.part.add(pos=[1.0, 1.0, 1.0])
    ns = {"system": system}
    cp = marble.checkpointing.Checkpoint(checkpoint_id="ro", checkpoint_path=str(tmp_path),
                                         namespace=ns)
    cp.register("system")
    cp.save(0)
    os.chmod(tmp_path / "ro", 0o555)
    try:
        with pytest.raises(RuntimeError, match="writing checkpoint .*1.checkpoint.*Permission"):
            cp.save(1)
        if marble.io.have_hdf5():
            with pytest.raises(RuntimeError, match="cannot create file"):
                marble.io.H5md(file_path=str(tmp_path / "ro" / "t.h5"), system=system)
    finally:
        os.chmod(tmp_path / "ro", 0o755)
    assert os.listdir(tmp_path / "ro") == ["0.checkpoint"]


# --- a rank dies ---------------------------------------------------------------------------

RANK_DEATH = textwrap.dedent("""
    import os, signal, sys, threading
    import numpy as np
    import marble
    how = sys.argv[1]
    system = marble.System(box_l=[12.0] * 3)
    system.time_step = 0.01
    system.cell_system.skin = 0.4
    rng = np.random.default_rng(5)
    system.part.add(pos=rng.random((3000, 3)) * 12.0, v=rng.normal(size=(3000, 3)))
    system.thermostat.set_dpd(kT=1.0, seed=1)
    system.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1, r_cut=1.0)
    system.integrator.run(5)
    rank = marble._marble.mpi_rank()
    print(f"rank {rank} running", flush=True)
    if rank == 1:
        if how == "sigkill":      # dies in the middle of a run
            threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGKILL)).start()
        else:                     # leaves between two collective calls
            os._exit(3)
    system.integrator.run(10 ** 7)
    print("NOT REACHED", flush=True)
""")


@pytest.mark.skipif(MPIEXEC is None, reason="no mpiexec")
@pytest.mark.skipif("MPI" not in marble._marble.build_options(), reason="built without MPI")
@pytest.mark.parametrize("how", ["sigkill", "exit"])
def test_rank_death_ends_the_job(tmp_path, how):
    script = tmp_path / "death.py"
    script.write_text(RANK_DEATH)
    t0 = time.time()
    try:
        p = subprocess.run([MPIEXEC, "-n", "2", sys.executable, str(script), how],
                           capture_output=True, text=True, timeout=180, env=mpi_env())
    except subprocess.TimeoutExpired:
        pytest.fail(f"mpiexec -n 2 hung after rank 1 died ({how}): killed after 180 s")
    out = p.stdout + p.stderr
    assert p.returncode != 0, out
    assert "NOT REACHED" not in out
    assert "rank 1 running" in out
    # Open MPI's launcher names the dead process
    if how == "sigkill":
        assert re.search(r"signal 9|Killed", out), out
    else:
        assert re.search(r"non-zero (exit )?(code|status)|exited", out), out
    print(f"{how}: job ended after {time.time() - t0:.1f} s with exit {p.returncode}")

