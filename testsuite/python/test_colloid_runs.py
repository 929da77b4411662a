# labels: python
"""The paper samples' integrator choice and their runs in pieces
(marble.colloid_runs, samples/marble_diffusion_vs_gamma.py; doc/paper-reproduction.md).

1. make_system(integrator="shardlow") integrates with Shardlow at the default
   dt (0.04 up to R = 2, 0.03 above); an unknown integrator or dt <= 0 is a
   ValueError, nothing built.
2. The sampling intervals follow the time step (every ~0.05 / 0.1 tau).
3. The Fig. 4 sample run in pieces (--stop-after, then --resume) gives the same
   runs, to the last bit, as one uninterrupted invocation: every (gamma, seed)
   run is done once, none is repeated or lost, and the summary is recomputed
   from all of them; a --resume with other settings is refused with a message
   that names the differing setting, and the file is left as it was.
"""
import json
import os
import subprocess
import sys
import tempfile

import pytest

import marble

pytestmark = pytest.mark.skipif(
    not marble.has_features("MARBLE", "DPD", "EXTERNAL_FORCE"),
    reason="missing feature MARBLE, DPD or EXTERNAL_FORCE")

from marble import colloid_runs as cr  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SAMPLE = os.path.join(HERE, "..", "..", "samples", "marble_diffusion_vs_gamma.py")


def test_integrator_choice():
    s, col, _ = cr.make_system(6.0, 1.5, 5.0, 1, integrator="shardlow", warmup=0.2)
    assert s.time_step == pytest.approx(0.04)
    assert s.integrator.get_state()["name"] == "Shardlow"
    assert cr.steps_for(s, 1.0) == 25 and cr.every(s, 0.05) == 1 and cr.every(s, 0.1) == 2
    s2, _, _ = cr.make_system(6.0, 1.5, 5.0, 1, warmup=0.0)
    assert s2.time_step == pytest.approx(0.01)
    assert s2.integrator.get_state()["name"] == "VelocityVerlet"
    assert cr.every(s2, 0.05) == 5 and cr.every(s2, 0.1) == 10
    # above R = 2 Shardlow's step takes RESPA substeps for the marble's WCA wall
    # (advisor.marble_dt, marble_substeps; doc/speed-accuracy.md)
    assert cr.default_dt("shardlow", 2.0) == 0.04 and cr.default_dt("shardlow", 3.0) == 0.06
    assert cr.default_substeps("shardlow", 2.0) == 1 and cr.default_substeps("shardlow", 3.0) == 3
    assert cr.default_dt("vv", 3.0) == 0.01 and cr.default_substeps("vv", 3.0) == 1
    assert s.integrator.get_state()["substeps"] == 1
    s3, _, _ = cr.make_system(8.0, 2.5, 5.0, 1, integrator="shardlow", warmup=0.0)
    assert s3.time_step == pytest.approx(0.06) and s3.integrator.get_state()["substeps"] == 3
    s4, _, _ = cr.make_system(8.0, 2.5, 5.0, 1, integrator="shardlow", dt=0.03, warmup=0.0)
    assert s4.integrator.get_state()["substeps"] == 1  # another dt: no substeps
    # the RESPA step rebuilds the lists every step at skin 0.4: its skin is 0.6
    assert s3.cell_system.skin == pytest.approx(0.6)
    assert s4.cell_system.skin == pytest.approx(0.4) and s2.cell_system.skin == pytest.approx(0.4)
    assert cr.default_skin("shardlow", 3.0) == 0.6 and cr.default_skin("shardlow", 2.0) == 0.4
    assert cr.default_skin("vv", 3.0) == 0.4 and cr.default_skin("shardlow", 3.0, dt=0.03) == 0.4
    s5, _, _ = cr.make_system(8.0, 2.5, 5.0, 1, integrator="shardlow", warmup=0.0, skin=0.5)
    assert s5.cell_system.skin == pytest.approx(0.5)
    with pytest.raises(ValueError, match="integrator must be one of"):
        cr.make_system(6.0, 1.5, 5.0, 1, integrator="euler")
    with pytest.raises(ValueError, match="dt must be > 0"):
        cr.make_system(6.0, 1.5, 5.0, 1, dt=0.0)


def _run(out, *extra):
    env = dict(os.environ, MARBLE_SAMPLE_TEST="1", MPLBACKEND="Agg")
    p = subprocess.run([sys.executable, SAMPLE, "--out", out, "--integrator", "shardlow", *extra],
                       env=env, capture_output=True, text=True, timeout=600)
    return p


def _runs(out):
    with open(os.path.join(out, "marble_diffusion_vs_gamma.json")) as f:
        data = json.load(f)
    return data, {(r["gamma"], r["seed"]): r for r in data["runs"]}


def test_pieces_equal_one_run():
    with tempfile.TemporaryDirectory() as whole, tempfile.TemporaryDirectory() as piece:
        p = _run(whole)
        assert p.returncode == 0, p.stdout + p.stderr
        ref, ref_runs = _runs(whole)
        assert ref["complete"] and len(ref_runs) == 4
        # first piece: stops after its first run (any run lasts longer than 1e-3 s)
        p = _run(piece, "--stop-after", "0.001")
        assert p.returncode == 0, p.stdout + p.stderr
        assert "3 runs left" in p.stdout
        first, first_runs = _runs(piece)
        assert not first["complete"] and len(first_runs) == 1
        p = _run(piece, "--resume")
        assert p.returncode == 0, p.stdout + p.stderr
        assert "1 runs already done, 3 to do" in p.stdout and "all runs done" in p.stdout
        data, runs = _runs(piece)
        assert data["complete"] and sorted(runs) == sorted(ref_runs)
        for k, r in ref_runs.items():
            for q in ("D_vacf", "D_msd", "D_drag", "D_drag_err"):
                assert runs[k][q] == r[q], (k, q)
        assert data["summary"] == ref["summary"]
        assert data["cpu_time_s"] == pytest.approx(sum(r["cpu_s"] for r in data["runs"]))
        # other settings: refused, file unchanged
        before = open(os.path.join(piece, "marble_diffusion_vs_gamma.json")).read()
        p = _run(piece, "--resume", "--dt", "0.02")
        assert p.returncode != 0
        assert "was made with dt = 0.04, this run has 0.02" in p.stderr
        assert open(os.path.join(piece, "marble_diffusion_vs_gamma.json")).read() == before
        # a piece from before the marble coupling moved into the Shardlow sweep (no key): refused
        assert data["marble_coupling"] == "shardlow_sweep"
        old = dict(data)
        del old["marble_coupling"]
        with open(os.path.join(piece, "marble_diffusion_vs_gamma.json"), "w") as f:
            json.dump(old, f)
        p = _run(piece, "--resume")
        assert p.returncode != 0
        assert "marble_coupling = 'explicit', this run has 'shardlow_sweep'" in p.stderr
        assert "before session 13" in p.stderr
