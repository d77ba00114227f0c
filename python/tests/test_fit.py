"""stickslip.fit against `stickslip fit --json`; partial fits, bad data,
pickling, figures."""

import pickle

import pytest

import stickslip
from stickslip import InputError

STEADY = ("steady", "examples/data/pmma-steady.csv")
ONSET = ("onset", "examples/data/pmma-onset.csv")


def test_equals_the_cli_json(root, cli, tmp_path, monkeypatch):
    monkeypatch.chdir(root)
    f = stickslip.fit("pmma", [STEADY, ONSET])
    expected = cli("fit", "--data", "steady=examples/data/pmma-steady.csv",
                   "--data", "onset=examples/data/pmma-onset.csv", "--out", str(tmp_path),
                   "--force")
    expected.pop("files")
    got = f.to_dict()
    got.pop("files")
    assert got == expected
    assert f.complete and f.stop is None
    # The seed's values within three standard errors.
    for name, truth in [("A", 0.012), ("B", 0.023), ("D0", 0.4)]:
        assert abs(f.value(name) - truth) < 3 * f.std_error(name), name
    assert f.scene().to_toml() and stickslip.hopf(f.scene()).found
    assert pickle.loads(pickle.dumps(f)) == f
    files = f.figures(tmp_path / "figs")
    assert any(p.endswith("-fit-onset-frequency_hz.png") for p in files)


def test_partial_and_bad_data(root, tmp_path, monkeypatch):
    monkeypatch.chdir(root)
    f = stickslip.fit("pmma", {"steady": "examples/data/pmma-steady.csv"})
    assert not f.complete and "D0" in f.stop
    assert f.parameters["D0"]["std_error"] is None
    bad = tmp_path / "bad.csv"
    bad.write_text("V_um_s,mu\n1,0.5\n0,0.49\n")
    with pytest.raises(InputError) as e:
        stickslip.fit("pmma", [("steady", bad)])
    assert "row 3, column 1 (V_um_s)" in str(e.value)
    with pytest.raises(InputError):
        stickslip.fit("pmma", [("stedy", bad)])


MACHINE = "examples/scenes/pmma-machine.toml"
STEP = ("velocity_step", "examples/data/pmma-velocity-step.csv")
RELAXATIONS = [("relaxation", f"examples/data/pmma-relaxation-{v}.csv") for v in ("0.3", "1", "3")]


def test_time_series_pass_through(root, cli, tmp_path, monkeypatch):
    monkeypatch.chdir(root)
    f = stickslip.fit(MACHINE, [STEP])
    expected = cli("fit", "--scene", MACHINE, "--data", "velocity_step=" + STEP[1],
                   "--out", str(tmp_path), "--force")
    expected.pop("files")
    got = f.to_dict()
    got.pop("files")
    assert got == expected
    assert f.complete
    for name, truth in [("A", 0.012), ("B", 0.023), ("D0", 0.4), ("mu0", 0.5)]:
        assert abs(f.value(name) - truth) < 3 * f.std_error(name), name
    step = got["datasets"][0]
    assert (step["kind"], step["rows"], step["model"]) == ("velocity_step", 2000, "quasi-static")
    files = f.figures(tmp_path / "figs")
    assert any(p.endswith("-fit-velocity_step-mu.png") for p in files)
    # Relaxations see no mu0: partial, named; without it, complete.
    partial = stickslip.fit(MACHINE, RELAXATIONS)
    assert not partial.complete and "mu0" in partial.stop
    r = stickslip.fit(MACHINE, RELAXATIONS, free="A,B,D0,mu2")
    assert r.complete and abs(r.value("mu2") - 2.4e-4) < 3 * r.std_error("mu2")
    bad = tmp_path / "bad.csv"
    bad.write_text("t_s,slip_um,V_um_s\n0,0,1\n1,0.1,3\n")
    with pytest.raises(InputError) as e:
        stickslip.fit(MACHINE, [("relaxation", bad)])
    assert "row 3, column 3 (V_um_s)" in str(e.value)


def test_an_adhesive_scene_is_fitted_with_its_own_law(root, cli, tmp_path, monkeypatch):
    """The gel: the JSON of `stickslip fit --scene gel --json`, the values
    of docs/reference/fit_adhesive_data.py within three standard errors,
    the fitted scene adhesive and read back by hopf."""
    monkeypatch.chdir(root)
    data = [("steady", "examples/data/gel-steady.csv"), ("onset", "examples/data/gel-onset.csv")]
    f = stickslip.fit("gel", data)
    expected = cli("fit", "--scene", "gel", "--data", "steady=examples/data/gel-steady.csv",
                   "--data", "onset=examples/data/gel-onset.csv", "--out", str(tmp_path),
                   "--force")
    expected.pop("files")
    got = f.to_dict()
    got.pop("files")
    assert got == expected
    assert got["law"] == "adhesive" and f.complete
    truth = {"F_a": 0.05, "V_s": 0.025, "tau_on": 0.1, "tau_out": 1.0, "F_v": 5e-4, "alpha": 0.6}
    for name, value in truth.items():
        assert abs(f.value(name) - value) < 3 * f.std_error(name), name
    assert 'law = "adhesive"' in f.fitted_toml
    hopf = stickslip.hopf(f.scene())
    assert hopf.to_dict()["critical"]["K_N_per_m"] > 0
    files = f.figures(tmp_path / "figs")
    assert any(p.endswith("-fit-steady-F_N.png") for p in files)
