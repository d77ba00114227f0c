"""Scenes: built-in, from TOML, from keys, overrides, TOML out, pickling, errors."""

import pickle

import pytest

import stickslip
from stickslip import InputError, Scene


def test_builtin_scenes_listed():
    names = stickslip.scenes()
    assert {"pmma", "pmma-rr", "brockley"} <= set(names)
    assert all(isinstance(d, str) and d for d in names.values())


def test_builtin_and_file_give_the_same_parameters(root):
    a = Scene.builtin("pmma")
    b = Scene.from_toml(root / "examples" / "scenes" / "pmma.toml")
    assert a.name == b.name == "pmma"
    assert a.params == b.params
    assert a.params["A"] == 0.012 and a.params["B"] == 0.023


def test_keys_in_physical_units():
    # kappa = K D0 / W, W = M g; nu = V / V0.
    s = Scene(name="block", A=0.01, B=0.02, D0=0.5, V0=1.0, M=2.0, g=10.0, K=1e5, V=3.0)
    assert s.name == "block"
    assert s.params["kappa"] == pytest.approx(1e5 * 0.5e-6 / 20.0, rel=1e-15)
    assert s.params["nu"] == 3.0
    assert s.units["W_N"] == 20.0


def test_overrides_physical_and_dimensionless():
    base = Scene.builtin("pmma")
    s = base.with_(K=2e5).with_(nu=3)
    assert s.overrides == ("K=200000.0", "nu=3.0")
    w = 9.81
    assert s.params["kappa"] == pytest.approx(2e5 * 0.4e-6 / w, rel=1e-14)
    assert s.params["nu"] == 3.0
    # A name given again replaces the earlier value; the base is unchanged.
    assert s.with_(K=3e5).overrides == ("nu=3.0", "K=300000.0")
    assert base.overrides == ()
    assert s.with_(V_range=(0.5, 50)).units["V_range_um_per_s"] == pytest.approx((0.5, 50.0), rel=1e-14)


def test_to_toml_round_trips_physical_overrides(tmp_path):
    s = Scene.builtin("pmma").with_(K=2e5, M=0.5)
    text = s.to_toml()
    f = tmp_path / "p.toml"
    f.write_text(text)
    back = Scene.from_toml(f)
    assert back.params == s.params
    assert back.name == "pmma"
    # A dimensionless override is no scene key: named in a comment.
    assert "# dimensionless overrides" in Scene.builtin("pmma").with_(kappa=0.01).to_toml()


def test_scene_pickles(tmp_path):
    f = tmp_path / "mine.toml"
    f.write_text('A = 0.01\nB = 0.02\nD0 = 1.0\n')
    for s in [
        Scene.builtin("brockley").with_(K=1e5, m=0.1),
        Scene.from_toml(f),
        Scene(A=0.01, B=0.02),
    ]:
        back = pickle.loads(pickle.dumps(s))
        assert back == s and back.params == s.params and back.name == s.name
    # The file's text is kept: the scene outlives the file.
    s = Scene.from_toml(f)
    f.unlink()
    assert pickle.loads(pickle.dumps(s)).name == "mine"


def test_errors_name_the_field(tmp_path):
    with pytest.raises(InputError) as e:
        Scene.builtin("pmma").with_(K=-1)
    assert isinstance(e.value, ValueError)
    assert e.value.field == "K" and "K = -1" in str(e.value)
    with pytest.raises(InputError) as e:
        Scene.builtin("pmma").with_(kapa=0.01)
    assert "kappa" in str(e.value)  # the suggestion
    with pytest.raises(InputError) as e:
        Scene(A=-0.01, B=0.02)
    assert e.value.field == "A"
    with pytest.raises(InputError) as e:
        Scene(A=0.01, Bee=0.02)
    assert "Bee" in str(e.value) and e.value.field == "scene key"
    with pytest.raises(InputError) as e:
        Scene.builtin("pmmma")
    assert "pmma" in str(e.value)
    f = tmp_path / "bad.toml"
    f.write_text("A = 0.01\nD0 = -2\n")
    with pytest.raises(InputError) as e:
        Scene.from_toml(f)
    assert e.value.field == "D0" and str(f) in str(e.value)
    # The exception pickles (process pools send it back).
    back = pickle.loads(pickle.dumps(e.value))
    assert isinstance(back, InputError) and back.field == e.value.field


def test_the_state_law_is_a_scene_key():
    """state_law = "slip" (issue 27): as a scene key, as an override, and
    written back by to_toml; the slip law's l1 is docs/reference/
    slip_law_l1.py's (-0.0200138669265728...) on PMMA's values."""
    s = stickslip.Scene.builtin("pmma").with_(state_law="slip")
    h = stickslip.hopf(s)
    assert h.l1 == pytest.approx(-0.0200138669265728284647869, rel=1e-12)
    assert s.params["state_law"] == "slip"
    text = s.to_toml()
    assert 'state_law = "slip"' in text, text
    custom = stickslip.Scene(A=0.012, B=0.023, mu2=2.4e-4, state_law="slip")
    assert stickslip.hopf(custom).l1 == pytest.approx(h.l1, rel=1e-14)
    with pytest.raises(stickslip.InputError):
        stickslip.hopf(stickslip.Scene.builtin("pmma").with_(state_law="dieterich"))


def test_radiation_damping_is_a_scene_key():
    """eta [s/m] (issue 27): eta_d = eta V0 with V0 in m/s; kappa_c with
    mu_v + eta_d nu (docs/model.md); with_(eta=...) and eta_d agree."""
    s = stickslip.Scene(A=0.012, B=0.023, V0=1.0, eta=5000.0)
    assert s.params["eta_d"] == pytest.approx(5e-3, rel=1e-15)
    h = stickslip.hopf(s)
    assert h.kappa_c == pytest.approx(0.023 - 0.012 - 5e-3, rel=1e-10)
    plain = stickslip.Scene(A=0.012, B=0.023, V0=1.0)
    assert plain.params["eta_d"] == 0.0
    assert plain.with_(eta=5000.0).params["eta_d"] == pytest.approx(5e-3, rel=1e-15)
    assert stickslip.hopf(plain.with_(eta_d=5e-3)).kappa_c == pytest.approx(h.kappa_c, rel=1e-12)
    with pytest.raises(stickslip.InputError):
        stickslip.hopf(plain.with_(eta=-1.0))
