# labels: python
"""Checkpoint/restart (doc/io.md): 2n steps equal n steps + checkpoint +
restart + n steps bit for bit (positions, velocities, forces, torques,
correlator and mean/variance state) with DPD and (with MARBLE) a marble colloid, for
velocity Verlet (restart in a new process), Shardlow and DPD-VV; corrupt,
truncated and foreign files are refused without changing anything; a crash
while writing leaves the previous checkpoint intact."""
import os
import pickle
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import marble
import marble.checkpointing
from marble.checkpointing import Checkpoint, CheckpointError

pytestmark = pytest.mark.skipif(not marble.has_features("DPD"), reason="missing feature DPD")

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from checkpoint_scene import dump, make_scene  # noqa: E402

N_HALF = 30


def assert_bitwise_equal(a, b):
    assert a.keys() == b.keys()
    for k in a:
        x, y = np.asarray(a[k]), np.asarray(b[k])
        assert x.shape == y.shape and x.dtype == y.dtype, k
        # bit for bit (NaN of unreached lags included)
        assert x.tobytes() == y.tobytes(), f"{k} differs: max |diff| " \
            f"{np.nanmax(np.abs(x.astype(float) - y.astype(float)))}"


def test_restart_in_new_process_vv(tmp_path):
    s, corr, mv = make_scene("vv")
    s.integrator.run(N_HALF)
    ns = dict(system=s, corr=corr, mv=mv, note={"n_half": N_HALF})
    cp = Checkpoint(checkpoint_id="vv", checkpoint_path=str(tmp_path), namespace=ns)
    cp.register("system", "corr", "mv", "note")
    assert cp.save() == 0
    s.integrator.run(N_HALF)
    ref = dump(s, corr, mv)

    out = tmp_path / "restarted.npz"
    script = tmp_path / "restart.py"
    script.write_text(textwrap.dedent(f"""
        import sys
        sys.path.insert(0, {HERE!r})
        import numpy as np
        import marble.checkpointing
        from checkpoint_scene import dump
        cp = marble.checkpointing.Checkpoint(checkpoint_id="vv", checkpoint_path={str(tmp_path)!r})
        assert cp.has_checkpoints() and cp.get_last_checkpoint_index() == 0
        cp.load()
        # shared references survive: the registered accumulators are the system's
        assert list(system.auto_update_accumulators) == [corr, mv]
        assert corr.obs1.system is system
        system.integrator.run(note["n_half"])
        np.savez({str(out)!r}, **dump(system, corr, mv))
    """))
    subprocess.run([sys.executable, str(script)], check=True, env=dict(os.environ), timeout=300)
    with np.load(out) as f:
        got = {k: f[k] for k in f.files}
    assert_bitwise_equal(ref, got)


@pytest.mark.parametrize("integrator", ["shardlow", "dpd_vv", "vv"])
def test_restart_in_process(integrator, tmp_path):
    s, corr, mv = make_scene(integrator)
    s.integrator.run(N_HALF)
    ns = dict(system=s, corr=corr, mv=mv)
    cp = Checkpoint(checkpoint_id=integrator, checkpoint_path=str(tmp_path), namespace=ns)
    cp.register("system", "corr", "mv")
    cp.save()
    s.integrator.run(N_HALF)
    ref = dump(s, corr, mv)
    ns2 = {}
    Checkpoint(checkpoint_id=integrator, checkpoint_path=str(tmp_path), namespace=ns2).load()
    s2 = ns2["system"]
    assert s2 is not s and s2.integrator.get_state() == s.integrator.get_state()
    assert s2.auto_update_accumulators[0] is ns2["corr"]
    s2.integrator.run(N_HALF)
    assert_bitwise_equal(ref, dump(s2, ns2["corr"], ns2["mv"]))


def test_pickle_round_trip_state():
    """A pickled System restores every core byte (the blob round-trips exactly)
    and its parameters."""
    s, corr, mv = make_scene("vv")
    s.integrator.run(5)
    s.my_label = "run A"
    s2, corr2 = pickle.loads(pickle.dumps((s, corr)))
    assert s2._core.get_checkpoint_state() == s._core.get_checkpoint_state()
    assert s2.my_label == "run A"
    assert corr2 in s2.auto_update_accumulators
    np.testing.assert_array_equal(s2.box_l, s.box_l)
    assert s2.time_step == s.time_step and s2.step == s.step
    assert s2.thermostat.dpd.philox_counter == s.thermostat.dpd.philox_counter
    assert s2.cell_system.skin == s.cell_system.skin
    if marble.has_features("MARBLE"):
        assert s2.non_bonded_inter[1, 0].marble.get_params() == \
            s.non_bonded_inter[1, 0].marble.get_params()


def _saved(tmp_path, cid="bad"):
    s, corr, mv = make_scene("vv")
    s.integrator.run(3)
    ns = dict(system=s, corr=corr)
    cp = Checkpoint(checkpoint_id=cid, checkpoint_path=str(tmp_path), namespace=ns)
    cp.register("system", "corr")
    cp.save()
    return s, ns, cp, cp._path(0)


def _corruptions(data):
    flipped = bytearray(data)
    flipped[len(data) // 2] ^= 0x10
    return {"truncated": data[:len(data) // 2], "flipped byte": bytes(flipped),
            "wrong magic": b"X" + data[1:], "empty": b""}


@pytest.mark.parametrize("kind", ["truncated", "flipped byte", "wrong magic", "empty"])
def test_corrupt_file_leaves_everything_unchanged(kind, tmp_path):
    s, ns, cp, path = _saved(tmp_path)
    s.integrator.run(2)  # the live system differs from the file
    before = s._core.get_checkpoint_state()
    old = dict(ns)
    with open(path, "rb") as f:
        data = f.read()
    with open(path, "wb") as f:
        f.write(_corruptions(data)[kind])
    with pytest.raises(CheckpointError, match="not a valid Marble checkpoint"):
        cp.load()
    assert ns == old and all(ns[k] is old[k] for k in old)
    assert s._core.get_checkpoint_state() == before


@pytest.mark.parametrize("kind", ["truncated", "flipped byte", "wrong magic", "empty"])
def test_corrupt_core_blob_leaves_system_unchanged(kind):
    s, _, _ = make_scene("vv")
    blob = s._core.get_checkpoint_state()
    s.integrator.run(2)
    before = s._core.get_checkpoint_state()
    with pytest.raises(RuntimeError, match="invalid Marble checkpoint data"):
        s._core.set_checkpoint_state(_corruptions(blob)[kind])
    assert s._core.get_checkpoint_state() == before
    s._core.set_checkpoint_state(blob)  # the intact blob loads
    assert s._core.get_checkpoint_state() == blob


def test_other_build_features_refused():
    """A blob from a build with other features (valid checksum) is refused."""
    import zlib
    s, _, _ = make_scene("vv")
    blob = bytearray(s._core.get_checkpoint_state())
    before = bytes(blob)
    head = 8 + 4 + 8 + 4
    # payload: u64 length + feature list; change its first letter
    blob[head + 8] = ord("Z")
    payload = bytes(blob[head:])
    assert marble._marble.crc32(payload) == zlib.crc32(payload)
    blob[head - 4:head] = zlib.crc32(payload).to_bytes(4, "little")
    with pytest.raises(RuntimeError, match="features"):
        s._core.set_checkpoint_state(bytes(blob))
    assert s._core.get_checkpoint_state() == before


def test_atomic_write(tmp_path, monkeypatch):
    s, ns, cp, path = _saved(tmp_path, cid="atomic")
    with open(path, "rb") as f:
        good = f.read()
    s.integrator.run(2)

    def crash(f, data):
        f.write(data[:len(data) // 3])
        raise OSError("simulated crash while writing")
    monkeypatch.setattr(marble.checkpointing, "_write_all", crash)
    with pytest.raises(RuntimeError, match="simulated crash"):
        cp.save(checkpoint_index=0)
    with open(path, "rb") as f:
        assert f.read() == good
    assert sorted(os.listdir(os.path.dirname(path))) == ["0.checkpoint"]
    monkeypatch.undo()
    assert cp.save() == 1 and cp.get_last_checkpoint_index() == 1
    ns2 = {}
    Checkpoint(checkpoint_id="atomic", checkpoint_path=str(tmp_path), namespace=ns2).load(0)
    assert ns2["system"].step == 3


def test_api_errors(tmp_path):
    with pytest.raises(ValueError, match="checkpoint_id"):
        Checkpoint(checkpoint_id="a/b", checkpoint_path=str(tmp_path))
    cp = Checkpoint(checkpoint_id="api", checkpoint_path=str(tmp_path), namespace={})
    assert not cp.has_checkpoints()
    with pytest.raises(CheckpointError, match="no checkpoints"):
        cp.get_last_checkpoint_index()
    with pytest.raises(ValueError, match="identifiers"):
        cp.register("not a name")
    cp.register("missing")
    with pytest.raises(ValueError, match="missing"):
        cp.save()
    with pytest.raises(ValueError, match="checkpoint_index"):
        cp.save(checkpoint_index=-1)
    with pytest.raises(CheckpointError, match="cannot read"):
        cp.load(checkpoint_index=7)


@pytest.mark.skipif(not marble.has_features("TUNABLE_SLIP", "LENNARD_JONES"),
                    reason="missing feature TUNABLE_SLIP or LENNARD_JONES")
def test_walls_and_time_series(tmp_path):
    """Tunable-slip walls (their ids, forces on the wall, the non-periodic
    axis) and a TimeSeries continue bit for bit."""
    import marble.accumulators
    import marble.observables
    from marble.shapes import Wall
    rng = np.random.default_rng(2)
    s = marble.System(box_l=[5.0, 5.0, 6.0], periodicity=[True, True, False])
    s.time_step = 0.01
    s.part.add(pos=rng.uniform([0, 0, 1.2], [5, 5, 4.8], (200, 3)), v=rng.normal(size=(200, 3)))
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0)
    for wt, nrm, dist in ((1, [0, 0, 1], 0.0), (2, [0, 0, -1], -6.0)):
        s.constraints.add(shape=Wall(normal=nrm, dist=dist), particle_type=wt)
        s.non_bonded_inter[wt, 0].lennard_jones.set_params(epsilon=1.0, sigma=1.0,
                                                           cutoff=2 ** (1 / 6), shift="auto")
        s.non_bonded_inter[wt, 0].tunable_slip.set_params(gamma=2.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=1.0, seed=3)
    ts = marble.accumulators.TimeSeries(
        obs=marble.observables.ParticlePositions(ids=[0, 5], system=s), delta_N=3)
    s.auto_update_accumulators.add(ts)
    s.integrator.run(20)
    ns = dict(system=s, ts=ts)
    cp = Checkpoint(checkpoint_id="walls", checkpoint_path=str(tmp_path), namespace=ns)
    cp.register("system", "ts")
    cp.save()
    s.integrator.run(20)
    ns2 = {}
    Checkpoint(checkpoint_id="walls", checkpoint_path=str(tmp_path), namespace=ns2).load()
    s2 = ns2["system"]
    assert len(s2.constraints) == 2 and s2.constraints[1].shape.dist == -6.0
    np.testing.assert_array_equal(s2.periodicity, [True, True, False])
    s2.integrator.run(20)
    for name in ("pos", "v", "f"):
        assert getattr(s2.part.all(), name).tobytes() == getattr(s.part.all(), name).tobytes()
    for c, c2 in zip(s.constraints, s2.constraints):
        assert c.total_force().tobytes() == c2.total_force().tobytes()
    assert ns2["ts"].time_series().tobytes() == ts.time_series().tobytes()


def test_fresh_system_without_forces(tmp_path):
    """A state with invalid lists and forces (particles just added, no run
    yet) continues bit for bit too: both recompute them the same way."""
    s, corr, mv = make_scene("dpd_vv")
    s.part.add(pos=[0.5, 0.5, 0.5], v=[0.1, 0.0, 0.0])  # invalidates lists and forces
    s2, corr2, mv2 = pickle.loads(pickle.dumps((s, corr, mv)))
    s.integrator.run(10)
    s2.integrator.run(10)
    assert_bitwise_equal(dump(s, corr, mv), dump(s2, corr2, mv2))


def test_steepest_descent_parameters():
    s, _, _ = make_scene("vv")
    s.integrator.set_steepest_descent(f_max=1.0, gamma=0.01, max_displacement=0.05)
    s2 = pickle.loads(pickle.dumps(s))
    assert s2.integrator.get_state() == s.integrator.get_state()
    assert s2._core.get_checkpoint_state() == s._core.get_checkpoint_state()


def test_older_format_version_refused():
    """A core blob of an older format version (2: before the Langevin/Brownian
    thermostats and per-particle gamma were stored) is refused with a message
    naming both versions; nothing changes."""
    s, _, _ = make_scene("vv")
    blob = bytearray(s._core.get_checkpoint_state())
    before = bytes(blob)
    version_at = 8  # after the 8-byte magic
    assert int.from_bytes(blob[version_at:version_at + 4], "little") == 8
    blob[version_at:version_at + 4] = (2).to_bytes(4, "little")
    with pytest.raises(RuntimeError, match="format version 2, this build reads versions 3 to 8"):
        s._core.set_checkpoint_state(bytes(blob))
    assert s._core.get_checkpoint_state() == before


def _global_block(blob):
    """(payload before the global block, the global block, the rest) of a
    core blob. Envelope: magic (8) | version (u32) | size (u64) | CRC-32
    (u32); payload: features (u64 + bytes), layout (u64 + bytes), i32 rank
    count, global block (u64 + bytes), particle blocks."""
    import struct
    head = 8 + 4 + 8 + 4
    p = bytes(blob[head:])
    at = 0
    for _ in range(2):  # features, layout
        n, = struct.unpack_from("<Q", p, at)
        at += 8 + n
    at += 4
    n_g, = struct.unpack_from("<Q", p, at)
    return p[:at], p[at + 8:at + 8 + n_g], p[at + 8 + n_g:]


def _with_global_block(blob, version, before, g, rest):
    """The core blob of format @p version with the global block @p g."""
    import struct
    import zlib
    p = before + struct.pack("<Q", len(g)) + g + rest
    return bytes(blob[:8]) + struct.pack("<IQI", version, len(p), zlib.crc32(p)) + p


def _as_version_3(blob):
    """The format-3 blob of the same state: format 4 appended the requested
    large-range types (i32 mode, u64 count, count bytes) to the global block."""
    import struct
    blob, _ = _as_version_6(blob)  # (without the fields of formats 7 and 8)
    before, g, rest = _global_block(blob)
    # format 6 appended the domain planes (three u64 counts and doubles; equal domains here: empty)
    assert g[len(g) - 24:] == bytes(24)
    g = g[:len(g) - 24]
    # format 5 appended the integrator's substeps (i32; no Lees-Edwards tail here)
    assert struct.unpack_from("<i", g, len(g) - 4)[0] == 1
    g = g[:len(g) - 4]
    # the appended field: find the count from the end (mode i32, count u64, bytes)
    for k in range(0, 256):
        if len(g) >= 12 + k and struct.unpack_from("<Q", g, len(g) - k - 8)[0] == k:
            mode, = struct.unpack_from("<i", g, len(g) - k - 12)
            if mode in (-1, 0, 1):
                g3 = g[:len(g) - k - 12]
                break
    else:
        raise AssertionError("no large-range field at the end of the global block")
    return _with_global_block(blob, 3, before, g3, rest), mode


needs_suspension = pytest.mark.skipif(
    not marble.has_features("DPD", "HAT", "CONTACT", "LUBRICATION", "MASS"),
    reason="needs DPD, HAT, CONTACT, LUBRICATION, MASS")


def _two_grid_suspension(mode):
    import marble.suspensions as sus
    s = marble.System(box_l=[9.0] * 3)
    s.time_step = 1e-3
    s.cell_system.skin = 0.4
    s.cell_system.large_range_types = mode
    sus.setup_suspension(s, phi=0.2, radius=1.0, kT=0.1, gamma=4.5, eta=0.3, seed=4, h_cut=1.0)
    s.integrator.set_shardlow()
    s.integrator.run(10)
    return s


@needs_suspension
@pytest.mark.parametrize("mode", [[1], None, "auto"])
def test_large_range_types_in_core_blob(mode):
    """cell_system.large_range_types is part of the core blob (format 4): a
    System restored from the bare blob (no Python-side state) has the same
    setting and grids and continues the two-grid (or one-grid) suspension bit
    for bit."""
    s = _two_grid_suspension(mode)
    grids = s.cell_system.get_state()["large_range_types"]
    assert grids == ([] if mode is None else [1])
    blob = s._core.get_checkpoint_state()
    s2 = marble.System(box_l=[4.0] * 3)  # another box: the blob sets everything
    s2._core.set_checkpoint_state(blob)
    assert s2.cell_system.large_range_types == mode
    assert s2._core.get_checkpoint_state() == blob
    s.integrator.run(25)
    s2.integrator.run(25)
    assert s2.cell_system.get_state()["large_range_types"] == grids
    a, b = s.part.all(), s2.part.all()
    for k in ("id", "pos", "v", "f"):
        assert np.asarray(getattr(a, k)).tobytes() == np.asarray(getattr(b, k)).tobytes(), k


@needs_suspension
def test_large_range_types_checkpoint_file(tmp_path):
    """Through marble.checkpointing (the pickled System) the non-default
    setting survives too, and the run continues bit for bit."""
    s = _two_grid_suspension([1])
    cp = Checkpoint(checkpoint_id="susp", checkpoint_path=str(tmp_path), namespace=dict(system=s))
    cp.register("system")
    cp.save()
    s.integrator.run(25)
    ns = {}
    Checkpoint(checkpoint_id="susp", checkpoint_path=str(tmp_path), namespace=ns).load()
    s2 = ns["system"]
    assert s2.cell_system.large_range_types == [1]
    assert "_large_range_types" not in s2.__dict__
    s2.integrator.run(25)
    assert s2.cell_system.get_state()["large_range_types"] == [1]
    a, b = s.part.all(), s2.part.all()
    for k in ("id", "pos", "v", "f"):
        assert np.asarray(getattr(a, k)).tobytes() == np.asarray(getattr(b, k)).tobytes(), k


def test_format_3_blob_loads_as_auto():
    """A blob of format version 3 (no large-range types) still loads, with
    large_range_types = "auto"; the state is otherwise the same."""
    s, _, _ = make_scene("vv")
    s.cell_system.large_range_types = None
    blob = s._core.get_checkpoint_state()
    old, mode = _as_version_3(blob)
    assert mode == 0
    s2 = marble.System(box_l=[4.0] * 3)
    s2._core.set_checkpoint_state(old)
    assert s2.cell_system.large_range_types == "auto"
    s2.cell_system.large_range_types = None
    s2.cell_system.list_check = "pairs"  # (older blobs load with the half-skin check)
    assert s2._core.get_checkpoint_state() == blob


def test_old_pickle_attribute_restores_the_setting():
    """Pickles written before format 4 kept the setting as the System
    attribute '_large_range_types'; it is still honoured."""
    s, _, _ = make_scene("vv")
    fn, args, state = s.__reduce__()
    state["extra"]["_large_range_types"] = [2]
    s2 = fn(*args)
    s2.__setstate__(state)
    assert s2.cell_system.large_range_types == [2]
    assert "_large_range_types" not in s2.__dict__


def _as_version_7(blob):
    """The format-7 blob of the same state: format 8 appended the Verlet list
    check (i32) to the global block (no Lees-Edwards tail here)."""
    import struct
    before, g, rest = _global_block(blob)
    check, = struct.unpack_from("<i", g, len(g) - 4)
    return _with_global_block(blob, 7, before, g[:-4], rest), check


def _as_version_6(blob):
    """The format-6 blob of the same state: format 7 appended the automatic
    load balance (32 bytes) to the global block (no Lees-Edwards tail here)."""
    import struct
    blob, _ = _as_version_7(blob)
    before, g, rest = _global_block(blob)
    fields = struct.unpack_from("<iiddq", g, len(g) - 32)  # every, by, damping, threshold, count
    return _with_global_block(blob, 6, before, g[:-32], rest), fields


def test_load_balance_settings_in_core_blob():
    """cell_system.set_load_balance is part of the core blob (format 7): a
    System restored from it (another box: the blob sets everything) reports
    the same settings; a blob of format 6 loads without an automatic
    balance; a bad value in the blob is refused, nothing changed."""
    import struct
    s, _, _ = make_scene("vv")
    s.cell_system.set_load_balance(25, by="pairs", damping=0.3, threshold=0.2)
    want = s.cell_system.get_load_balance()
    blob = s._core.get_checkpoint_state()
    s2 = marble.System(box_l=[4.0] * 3)
    s2._core.set_checkpoint_state(blob)
    assert s2.cell_system.get_load_balance() == want
    assert pickle.loads(pickle.dumps(s)).cell_system.get_load_balance() == want
    old, fields = _as_version_6(blob)
    assert fields == (25, 2, 0.3, 0.2, 0)  # every, by (pairs), damping, threshold, balances
    s3 = marble.System(box_l=[4.0] * 3)
    s3._core.set_checkpoint_state(old)
    assert s3.cell_system.get_load_balance()["every"] == 0
    s3.cell_system.set_load_balance(25, by="pairs", damping=0.3, threshold=0.2)
    s3.cell_system.list_check = "pairs"  # (a format-6 blob loads with the half-skin check)
    assert s3._core.get_checkpoint_state() == blob
    # damping 0 in the blob (set_load_balance allows (0, 1]): refused as corrupt
    before_g, g, rest = _global_block(blob)
    at = len(g) - 4 - 32 + 8  # the damping: after every and by (and before the list check)
    assert struct.unpack_from("<d", g, at)[0] == 0.3
    bad = _with_global_block(blob, 8, before_g, g[:at] + struct.pack("<d", 0.0) + g[at + 8:], rest)
    before = s2._core.get_checkpoint_state()
    with pytest.raises(RuntimeError, match="load-balance settings"):
        s2._core.set_checkpoint_state(bad)
    assert s2._core.get_checkpoint_state() == before


def test_list_check_in_core_blob():
    """cell_system.list_check is part of the core blob (format 8): a System
    restored from it reports the same check; a blob of format 7 (written by a
    build that had only the half-skin test) loads with "half_skin"; a bad
    value in the blob is refused, nothing changed."""
    import struct
    s, _, _ = make_scene("vv")
    assert s.cell_system.list_check == "pairs"
    for check in ("half_skin", "pairs"):
        s.cell_system.list_check = check
        blob = s._core.get_checkpoint_state()
        s2 = marble.System(box_l=[4.0] * 3)
        s2._core.set_checkpoint_state(blob)
        assert s2.cell_system.list_check == check
        assert pickle.loads(pickle.dumps(s)).cell_system.list_check == check
    old, check = _as_version_7(blob)
    assert check == 0  # pairs
    s3 = marble.System(box_l=[4.0] * 3)
    s3._core.set_checkpoint_state(old)
    assert s3.cell_system.list_check == "half_skin"
    s3.cell_system.list_check = "pairs"
    assert s3._core.get_checkpoint_state() == blob
    before_g, g, rest = _global_block(blob)
    bad = _with_global_block(blob, 8, before_g, g[:-4] + struct.pack("<i", 5), rest)
    before = s2._core.get_checkpoint_state()
    with pytest.raises(RuntimeError, match="Verlet list check"):
        s2._core.set_checkpoint_state(bad)
    assert s2._core.get_checkpoint_state() == before
