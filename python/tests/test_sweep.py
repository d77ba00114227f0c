"""stickslip.sweep: grids, failed points, the local pool against Dask,
an interrupted sweep resumed, and the speed of 10 000 Hopf points."""

import os
import pathlib
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import stickslip
from stickslip import InputError, Scene

pd = pytest.importorskip("pandas")

GRID = {"K": [1e5, 2e5, -1.0], "V": [0.5, 5.0]}


@pytest.fixture(scope="module")
def local():
    return stickslip.sweep("hopf", GRID, scene="pmma", chunk=2)


def test_a_row_per_point_with_its_status(local):
    assert len(local) == 6 and list(local["point"]) == list(range(6))
    assert list(local.columns[:5]) == ["point", "K", "V", "status", "message"]
    bad = local[local["K"] < 0]
    assert set(bad["status"]) == {"input_error"} and all("K" in m for m in bad["message"])
    good = local[local["K"] > 0]
    assert set(good["status"]) == {"ok"}
    for _, row in good.iterrows():
        h = stickslip.hopf(Scene.builtin("pmma").with_(K=row["K"], V=row["V"]))
        assert row["kappa_c"] == h.kappa_c and row["l1"] == h.l1
        assert row["l1_error_bound"] == h.l1_error_bound and row["criticality"] == h.criticality
        assert row["result.status"] == h.status


def test_grids_as_lists_in_this_process():
    points = [{"K": 2e5}, {"K": 3e5, "m": 0.1}]
    t = stickslip.sweep("hopf", points, workers=0)
    assert list(t["K"]) == [2e5, 3e5] and np.isnan(t["m"][0]) and t["m"][1] == 0.1
    scenes = [Scene.builtin("pmma"), Scene.builtin("brockley")]
    t = stickslip.sweep("hopf", scenes, workers=0)
    assert list(t["scene"]) == ["pmma", "brockley"]
    assert list(t["result.status"]) == ["hopf", "stable_for_all_stiffness"]
    with pytest.raises(InputError):
        stickslip.sweep("fit", points)


def test_diagram_and_cycles_sweeps():
    d = stickslip.sweep("diagram", {"A": [0.010, 0.012]}, scene="pmma", workers=0)
    assert list(d["status"]) == ["ok", "ok"] and (d["n_hopf_curve"] > 10).all()
    c = stickslip.sweep("cycles", {"K": [2e5, 2.2e5]}, scene="pmma", kappa_fraction=0.9)
    assert list(c["status"]) == ["ok", "ok"] and (c["n_cycles"] > 3).all()
    one = stickslip.cycles(Scene.builtin("pmma").with_(K=2e5), kappa_fraction=0.9)
    assert c["delta_s_N_max"][0] == one.delta_s_N.max()


def test_dask_local_cluster_equals_the_local_sweep(local, capsys):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            t0 = time.perf_counter()
            remote = stickslip.sweep("hopf", GRID, scene="pmma", client=client, chunk=2)
            elapsed = time.perf_counter() - t0
    pd.testing.assert_frame_equal(remote, local)
    with capsys.disabled():
        print(f"\nLocalCluster (2 workers): {len(remote)} points in {elapsed:.2f} s, "
              "equal to the local sweep")


SCRIPT = """
import stickslip, sys
stickslip.sweep("cycles", {{"K": [1.9e5, 2.0e5, 2.1e5, 2.2e5, 2.3e5, 2.4e5]}}, scene="pmma",
                chunk=1, out=sys.argv[1], kappa_fraction=0.8, workers={workers})
"""


@pytest.mark.parametrize("workers", [1, 2])
def test_an_interrupted_sweep_resumes(tmp_path, workers):
    out = tmp_path / "sweep"
    p = subprocess.Popen([sys.executable, "-c", SCRIPT.format(workers=workers), str(out)],
                         stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 60
    while not list(out.glob("chunk-*.json")) and time.time() < deadline and p.poll() is None:
        time.sleep(0.02)
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=60)
    assert p.returncode != 0 and "KeyboardInterrupt" in err
    kept = {f.name: f.stat().st_mtime_ns for f in out.glob("chunk-*.json")}
    assert 1 <= len(kept) < 6, kept
    options = dict(chunk=1, out=out, kappa_fraction=0.8, workers=0)
    grid = {"K": [1.9e5, 2.0e5, 2.1e5, 2.2e5, 2.3e5, 2.4e5]}
    resumed = stickslip.sweep("cycles", grid, scene="pmma", **options)
    # The chunks written before the interruption are read, not computed again.
    assert {f.name: f.stat().st_mtime_ns for f in out.glob("chunk-*.json") if f.name in kept} == kept
    assert len(list(out.glob("chunk-*.json"))) == 6
    fresh = stickslip.sweep("cycles", grid, scene="pmma", chunk=1, kappa_fraction=0.8, workers=0)
    pd.testing.assert_frame_equal(resumed, fresh)
    assert (resumed["status"] == "ok").all()
    # Another sweep into the same directory is refused.
    with pytest.raises(InputError) as e:
        stickslip.sweep("cycles", grid, scene="pmma", chunk=1, out=out, kappa_fraction=0.7)
    assert e.value.field == "out"


def test_speed_of_ten_thousand_hopf_points(capsys):
    grid = {"K": np.linspace(1e5, 4e5, 100), "V": np.geomspace(0.1, 100, 100)}
    t0 = time.perf_counter()
    t = stickslip.sweep("hopf", grid, scene="pmma")
    elapsed = time.perf_counter() - t0
    assert len(t) == 10_000 and (t["status"] == "ok").all()
    assert t["kappa_c"].notna().all() and t["l1_error_bound"].notna().all()
    with capsys.disabled():
        print(f"\nsweep of 10 000 Hopf points (kappa_c, l1 with its bound) on "
              f"{os.cpu_count()} cores: {elapsed:.2f} s")


def test_without_pandas_a_structured_array(monkeypatch):
    import builtins

    real = builtins.__import__

    def no_pandas(name, *args, **kwargs):
        if name == "pandas" or name.startswith("pandas."):
            raise ImportError(name)
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_pandas)
    t = stickslip.sweep("hopf", {"K": [2e5, -1.0]}, workers=0)
    assert isinstance(t, np.ndarray) and t.dtype.names[:4] == ("point", "K", "status", "message")
    assert list(t["status"]) == ["ok", "input_error"] and np.isnan(t["kappa_c"][1])
