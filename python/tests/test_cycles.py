"""stickslip.cycles against the command line's JSON; arrays, partial
results, Ctrl-C, pickling, errors."""

import os
import pickle
import signal
import threading
import time

import numpy as np
import pytest

import stickslip
from stickslip import InputError, NumericalError, Scene

PMMA_K = Scene.builtin("pmma").with_(K=2e5)


def _without_files(d):
    d = dict(d)
    d.pop("files")
    # The command line writes the orbits to a file and names it; Python
    # only with orbits_file=.
    d.pop("orbits_file")
    return d


@pytest.fixture(scope="module")
def branch():
    """A short branch of the PMMA scene with a cycle at a requested stiffness."""
    return stickslip.cycles(PMMA_K, kappa_fraction=0.9, at={"K": [2.0e5]})


def test_equals_the_cli_json(cli, branch):
    expected = cli("cycles", "--scene", "pmma", "--set", "K=200000.0",
                   "--kappa-fraction", "0.9", "--at", "K=200000.0")
    assert _without_files(branch.to_dict()) == _without_files(expected)
    assert branch.to_dict()["files"] == []
    assert branch.complete and len(branch) > 3


def test_the_cycle_at_the_scenes_k_first(cli, root):
    """The rig (K = 2e5 N/m) at 1 um/s: the cycle at its K, delivered
    before the branch, as the command line's `operating_point`."""
    rig = str(root / "examples" / "scenes" / "rig.toml")
    r = stickslip.cycles(Scene.from_toml(rig).with_(V=1.0), max_steps=2)
    expected = cli("cycles", "--scene", rig, "--set", "V=1.0", "--max-steps", "2", expect=4)
    assert r.operating_point == expected["operating_point"]
    op = r.operating_point
    assert op["regime"] == "stick-slip" and op["method"] == "simulation"
    assert op["cycle"]["K_N_per_m"] == pytest.approx(2e5, rel=1e-15)
    assert op["cycle"]["period_s"] == pytest.approx(439.5281, rel=1e-6)
    assert op["slip_um"] == pytest.approx(1.0 * op["cycle"]["period_s"], rel=1e-14)
    # Without K in the scene: no operating point (the JSON as before).
    assert stickslip.cycles("pmma", kappa_fraction=0.99).operating_point is None


def test_columns_are_arrays(branch):
    d = branch.to_dict()["cycles"]
    assert isinstance(branch.kappa, np.ndarray) and branch.kappa.dtype == np.float64
    assert branch.kappa.tolist() == [c["kappa"] for c in d]
    assert branch.delta_s_N.tolist() == [c["delta_s_N"] for c in d]
    assert branch.ntst.dtype == np.int64 and branch.user_point.dtype == bool
    assert branch.user_point.sum() == 1
    # One array per scalar column of the cycles table, nothing JSON-only.
    assert "multipliers" not in branch.table and "period_s" in branch.table
    assert len(branch.orbits) == len(branch)
    o = branch.orbit(0)
    assert o["t_over_T"][0] == 0.0 and np.all(np.diff(o["t_over_T"]) > 0)
    assert branch.orbits[0].shape[1] == 4
    # The orbit's spring force spans Delta_s (the samples' extremes).
    assert np.ptp(o["s"]) == pytest.approx(d[0]["delta_s"], rel=1e-2)
    assert branch.multipliers[0].dtype == complex


def test_pickles_and_pandas(branch):
    back = pickle.loads(pickle.dumps(branch))
    assert back.to_dict() == branch.to_dict()
    assert np.array_equal(back.kappa, branch.kappa)
    assert all(np.array_equal(a, b) for a, b in zip(back.orbits, branch.orbits))
    pd = pytest.importorskip("pandas")
    df = branch.to_pandas()
    assert list(df["kappa"]) == list(branch.kappa) and "K_N_per_m" in df


def test_partial_at_max_steps(cli):
    r = stickslip.cycles(PMMA_K, kappa_fraction=0.5, max_steps=3)
    assert not r.complete and "3" in r.stop
    expected = cli("cycles", "--scene", "pmma", "--set", "K=200000.0",
                   "--kappa-fraction", "0.5", "--max-steps", "3", expect=4)
    assert _without_files(r.to_dict()) == _without_files(expected)


def test_ctrl_c_keeps_the_cycles():
    # SIGINT while the branch is computed (the GIL released): the branch
    # stops at the next cycle and what was computed is returned.
    timer = threading.Timer(2.0, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        r = stickslip.cycles(PMMA_K, kappa_fraction=0.01, max_steps=100000)
    finally:
        timer.cancel()
    assert r.interrupted and not r.complete
    assert len(r) > 0 and len(r.orbits) == len(r)
    assert "interrupted" in r.stop.lower() or "ctrl-c" in r.stop.lower()


def test_gil_released():
    # Another Python thread runs while the branch is computed.
    out = []
    worker = threading.Thread(target=lambda: out.append(stickslip.cycles(PMMA_K, kappa_fraction=0.9)))
    ticks, start = 0, time.perf_counter()
    worker.start()
    while worker.is_alive():
        ticks += 1
        time.sleep(0.001)
    elapsed = time.perf_counter() - start
    assert out and out[0].complete
    # Held by the job, the GIL would let this thread run about once per cycle.
    assert ticks > 2 * len(out[0]), (ticks, len(out[0]), elapsed)


def test_errors_name_the_field():
    for options, field in [
        ({"kappa_fraction": 1.5}, "kappa_fraction"),
        ({"ntst": 2}, "ntst"),
        ({"at": {"K": [-1.0]}}, "at K"),
        ({"at": {"Kay": [1.0]}}, "at stiffness"),
        ({"at_kappa": [0.0]}, "at_kappa"),
        ({"collocation": "lobatto"}, "collocation"),
    ]:
        with pytest.raises(InputError) as e:
            stickslip.cycles(PMMA_K, **options)
        assert e.value.field == field, (options, str(e.value))
        assert "--" not in str(e.value)
    with pytest.raises(InputError) as e:
        stickslip.cycles(PMMA_K, to=1e5)
    assert "param" in str(e.value)


def test_numerical_error_carries_the_partial_result():
    # A mesh that may not be refined cannot resolve the cycles far from onset.
    with pytest.raises(NumericalError) as e:
        stickslip.cycles(PMMA_K, kappa_fraction=0.2, ntst=8, ntst_max=8)
    partial = e.value.partial
    assert isinstance(partial, stickslip.Cycles) and not partial.complete
    assert len(partial.orbits) == len(partial)
    assert "ntst_max" in str(e.value) or "mesh" in str(e.value).lower()
