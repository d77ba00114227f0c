"""stickslip.simulate against the command line's CSV and text; Ctrl-C,
the GIL, pickling, figures, errors; cycles in a control parameter."""

import os
import pickle
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import stickslip
from stickslip import InputError, Scene

SCENE = Scene.builtin("pmma").with_(kappa=0.009)


def _e(x: float) -> str:
    """`x` as Rust's `{:.6e}` writes it (7.755615e0)."""
    mantissa, exponent = f"{x:.6e}".split("e")
    return f"{mantissa}e{int(exponent)}"


@pytest.fixture(scope="module")
def run():
    return stickslip.simulate(SCENE, protocol=[(1, 300)])


def test_equals_the_cli_csv_and_text(run, root, tmp_path):
    from conftest import _binary

    p = subprocess.run(
        [str(_binary()), "simulate", "--scene", "pmma", "--set", "kappa=0.009",
         "--protocol", "1:300", "--out", str(tmp_path), "--force"],
        capture_output=True, text=True, cwd=root,
    )
    assert p.returncode == 0, p.stderr
    csv = tmp_path / "pmma_kappa=0.009-simulation.csv"
    header = csv.read_text().splitlines()[0].split(",")
    assert tuple(header) == stickslip.SIMULATION_COLUMNS
    rows = np.genfromtxt(csv, delimiter=",", skip_header=1, dtype=None, encoding="utf-8")
    assert len(rows) == len(run) == run.steps
    for i, name in enumerate(header):
        column = np.array([r[i] for r in rows])
        if name == "model":
            assert list(column) == list(run.model)
        else:
            # The CSV's 12 significant digits.
            assert np.allclose(column.astype(float), getattr(run, name), rtol=2e-12, atol=0), name
    r = run.regime
    assert r["kind"] == "periodic"
    assert f"period {_e(r['period_s'])} s, force drop {_e(r['force_drop_N'])} N" in p.stdout
    assert f"slip per event {_e(r['slip_um'])} µm" in p.stdout
    assert f"{run.steps} steps over" in p.stdout
    assert run.complete and run.stop is None


def test_to_dict_equals_the_cli_json(run, cli):
    """`simulate --json` and `to_dict()`: the same keys and numbers (the
    CLI's `files` aside); `units`, `complete` and `stop` as in every
    command's JSON."""
    expected = cli("simulate", "--scene", "pmma", "--set", "kappa=0.009", "--protocol", "1:300")
    files = expected.pop("files")
    assert any(f.endswith("-simulation.csv") for f in files)
    assert run.to_dict() == expected
    assert expected["units"] == {"D0_um": 0.39999999999999997, "V0_um_per_s": 1.0}
    assert expected["complete"] is True and expected["stop"] is None
    short = cli("simulate", "--scene", "pmma", "--set", "kappa=0.009", "--protocol", "1:300",
                "--max-steps", "50", expect=4)
    assert short["complete"] is False and short["stop"].startswith("step limit: 50 steps")
    assert stickslip.simulate(SCENE, protocol=[(1, 300)], max_steps=50).to_dict() == {
        k: v for k, v in short.items() if k != "files"}


def test_columns_pandas_pickle_figures(run, tmp_path):
    assert run.t_s.dtype == np.float64 and np.all(np.diff(run.t_s) > 0)
    assert run.t_s[-1] == pytest.approx(300.0, rel=1e-12)
    assert set(run.model) <= {"quasi-static", "inertial"}
    pd = pytest.importorskip("pandas")
    df = run.to_pandas()
    assert list(df.columns) == list(stickslip.SIMULATION_COLUMNS) and len(df) == len(run)
    back = pickle.loads(pickle.dumps(run))
    assert back == run and np.array_equal(back.v_um_per_s, run.v_um_per_s)
    files = run.figures(tmp_path)
    assert sorted(f.rsplit("/", 1)[-1] for f in files) == [
        "pmma_kappa=0.009-simulation-spring-force.png",
        "pmma_kappa=0.009-simulation-spring-force.svg",
        "pmma_kappa=0.009-simulation-velocity.png",
        "pmma_kappa=0.009-simulation-velocity.svg",
    ]


def test_partial_at_max_steps():
    r = stickslip.simulate(SCENE, protocol="1:300", max_steps=100)
    assert not r.complete and len(r) == 100 and "step limit" in r.stop and r.regime is None


def test_ctrl_c_keeps_the_steps_and_the_gil_is_released():
    timer = threading.Timer(1.0, os.kill, (os.getpid(), signal.SIGINT))
    ticks = [0]
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks[0] += 1
            time.sleep(0.001)

    ticker = threading.Thread(target=tick)
    ticker.start()
    timer.start()
    try:
        r = stickslip.simulate(SCENE, protocol=[(1, 1e7)], max_steps=10**8, plot_points=1000)
    finally:
        timer.cancel()
        stop.set()
        ticker.join()
    assert r.interrupted and not r.complete and "interrupted" in r.stop
    assert len(r) > 1000 and r.t_s[-1] < 1e7
    # Held by the job, the GIL would starve the ticking thread.
    assert ticks[0] > 100


def test_errors_name_the_field():
    for options, field in [
        ({"rtol": 1.0}, "rtol"),
        ({"perturb": 2.0}, "perturb"),
        ({"plot_points": 1}, "plot_points"),
        ({"protocol": [(1, -5)]}, "protocol"),
        ({"protocol": [(1,)]}, "protocol"),
    ]:
        with pytest.raises(InputError) as e:
            stickslip.simulate(SCENE, **options)
        assert e.value.field == field, (options, str(e.value))
        assert "--" not in str(e.value)


def test_cycles_in_the_driving_velocity_equal_the_cli(cli, tmp_path):
    scene = Scene.builtin("pmma").with_(K=4e5)
    c = stickslip.cycles(scene, param="V", to=300, search=(1, 1000), at={"V": [250]})
    expected = cli("cycles", "--scene", "pmma", "--set", "K=400000.0", "--param", "V",
                   "--to", "300", "--search", "1:1000", "--at", "V=250")
    d = c.to_dict()
    assert d["files"] == []
    # The command line writes the orbits to a file; Python only with orbits_file=.
    assert d["orbits_file"] is None and expected["orbits_file"].endswith("-orbits.jsonl")
    for k in ("files", "orbits_file"):
        d.pop(k), expected.pop(k)
    assert d == expected
    assert c.complete and c.V_um_per_s.dtype == np.float64
    assert c.V_um_per_s.tolist() == [x["V_um_per_s"] for x in d["cycles"]]
    assert c.user_point.sum() == 1
    assert c.figures(tmp_path) == []  # the command line draws none for these
    with pytest.raises(InputError) as e:
        stickslip.cycles(scene, param="V")
    assert "to" in str(e.value)


def test_cycle_branch_figures(tmp_path):
    c = stickslip.cycles(Scene.builtin("pmma").with_(K=2e5), kappa_fraction=0.9)
    files = [f.rsplit("/", 1)[-1] for f in c.figures(tmp_path)]
    # Named as the command line names them.
    assert files and all(f.startswith("pmma_K_N_per_m=2e5-cycles") for f in files), files
    assert any(f.endswith(".png") for f in files) and any(f.endswith(".svg") for f in files)
