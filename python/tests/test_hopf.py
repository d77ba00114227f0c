"""stickslip.hopf against the command line's JSON and Appendix C."""

import pickle

import pytest

import stickslip
from stickslip import InputError, Scene


def _cli_args(scene: Scene) -> list[str]:
    args = ["--scene", scene._builtin or scene._origin]
    for item in scene.overrides:
        args += ["--set", item]
    return args


CASES = [
    (Scene.builtin("pmma"), {}),
    (Scene.builtin("pmma").with_(K=2e5), {}),
    (Scene.builtin("pmma").with_(kappa=0.0105, m=0.1, nu=3), {}),
    (Scene.builtin("pmma-rr"), {"model": "quasi-static"}),
    (Scene.builtin("brockley"), {}),
    (Scene.builtin("pmma").with_(K=4e5), {"param": "V", "to": 1000.0}),
]


@pytest.mark.parametrize("scene,options", CASES, ids=lambda x: repr(x))
def test_equals_the_cli_json(cli, scene, options):
    h = stickslip.hopf(scene, **options)
    args = ["hopf", *_cli_args(scene)]
    for name, value in options.items():
        args += [f"--{name.rstrip('_')}", str(value)]
    assert h.to_dict() == cli(*args)
    assert h.complete


def test_kappa_c_is_appendix_c():
    # C11: kappa_c = (mu_phi - mu_v) (1 + m nu^2 / mu_v); quasi-static (C12) m = 0.
    for scene, options in [
        (Scene.builtin("pmma"), {}),
        (Scene.builtin("pmma").with_(m=0.1, nu=3), {"model": "inertial"}),
        (Scene.builtin("pmma-rr").with_(m=0.5, nu=10), {}),
    ]:
        h = stickslip.hopf(scene, **options)
        assert h.found
        d = h.to_dict()
        p = d["params"]
        mu_v, mu_phi = d["mu_v"], d["mu_phi"]
        m = p["m"] if h.model == "inertial" else 0.0
        closed = (mu_phi - mu_v) * (1 + m * p["nu"] ** 2 / mu_v)
        assert h.kappa_c == pytest.approx(closed, rel=1e-10)
        assert h.appendix_c["kappa_c"] == pytest.approx(closed, rel=1e-14)
        assert h.omega_c == pytest.approx(p["nu"] * (mu_phi / mu_v - 1) ** 0.5, rel=1e-10)


def test_plain_law_quasi_static_is_b_minus_a_and_degenerate():
    s = Scene.builtin("pmma-rr")
    h = stickslip.hopf(s, model="quasi-static")
    assert h.kappa_c == pytest.approx(s.params["B"] - s.params["A"], rel=1e-12)
    assert h.criticality == "degenerate"


def test_physical_stiffness_and_operating_point():
    s = Scene.builtin("pmma").with_(K=2e5)
    h = stickslip.hopf(s)
    assert h.K_c == pytest.approx(h.kappa_c * s.units["W_N"] / (s.units["D0_um"] * 1e-6), rel=1e-14)
    assert h.operating_point["K_N_per_m"] == pytest.approx(2e5, rel=1e-15)
    assert h.note and "not used" in h.note


def test_no_onset_where_friction_strengthens():
    h = stickslip.hopf("brockley")
    assert not h.found and h.status == "stable_for_all_stiffness" and h.kappa_c is None


def test_result_pickles_and_tabulates():
    h = stickslip.hopf("pmma")
    back = pickle.loads(pickle.dumps(h))
    assert back == h and back.to_dict() == h.to_dict() and back.kappa_c == h.kappa_c
    pd = pytest.importorskip("pandas")
    df = h.to_pandas()
    assert isinstance(df, pd.DataFrame) and len(df) == 1
    assert df["kappa_c"][0] == h.kappa_c


def test_errors_name_the_field():
    with pytest.raises(InputError) as e:
        stickslip.hopf("pmma", param="velocity")
    assert e.value.field.startswith("param") and "V" in str(e.value)
    with pytest.raises(InputError) as e:
        stickslip.hopf("pmma", to=3.0)
    assert "to" in str(e.value) and "--" not in str(e.value)
    with pytest.raises(InputError) as e:
        stickslip.hopf("pmma", inertia_threshold=-1)
    assert e.value.field == "inertia_threshold"
    with pytest.raises(InputError) as e:
        stickslip.hopf("pmma", model="massive")
    assert e.value.field == "model"
