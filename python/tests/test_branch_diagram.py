"""stickslip.branch and stickslip.diagram against the command line's JSON;
arrays, partial results, pickling, figures, errors."""

import pickle

import numpy as np
import pytest

import stickslip
from stickslip import InputError, Scene

PMMA_K = Scene.builtin("pmma").with_(K=2e5)


def _without(d, *keys):
    d = dict(d)
    for k in keys:
        d.pop(k, None)
    return d


def test_branch_equals_the_cli_json(cli):
    b = stickslip.branch(PMMA_K, param="nu", max_steps=200)
    assert b.to_dict() == cli("branch", "--scene", "pmma", "--set", "K=200000.0",
                              "--param", "nu", "--max-steps", "200")
    assert b.complete and b.stop is None and b.param == "nu"
    assert isinstance(b.nu, np.ndarray) and b.nu.tolist() == [p["nu"] for p in b.to_dict()["points"]]
    assert b.eigenvalues.shape == (len(b), 3) and b.eigenvalues.dtype == complex
    assert b.n_unstable.dtype == np.int64


def test_branch_in_a_control_with_a_hopf_point(cli):
    # Steady sliding across the onset in the stiffness, in N/m.
    b = stickslip.branch("pmma", param="K", from_=4e5, to=1e5)
    assert b.to_dict() == cli("branch", "--scene", "pmma", "--param", "K",
                              "--from", "400000.0", "--to", "100000.0")
    ev = b.events
    assert list(ev["event"]) == ["hopf"]
    h = stickslip.hopf("pmma")
    assert ev["kappa"][0] == pytest.approx(h.kappa_c, rel=1e-8)
    assert b.to_dict()["control"]["param"] == "K"


def test_branch_partial_at_max_steps_and_pickles(cli):
    b = stickslip.branch(PMMA_K, param="K", max_steps=5)
    assert not b.complete and "--max-steps 5" in b.stop  # as the JSON says it
    expected = cli("branch", "--scene", "pmma", "--set", "K=200000.0", "--param", "K",
                   "--max-steps", "5", expect=4)
    assert b.to_dict() == expected
    back = pickle.loads(pickle.dumps(b))
    assert back == b and np.array_equal(back.kappa, b.kappa)
    pytest.importorskip("pandas")
    assert list(b.to_pandas()["kappa"]) == list(b.kappa)


def test_branch_errors_name_the_field():
    with pytest.raises(InputError) as e:
        stickslip.branch("pmma", param="velocity")
    assert e.value.field.startswith("param")
    with pytest.raises(InputError) as e:
        stickslip.branch("pmma", param="nu", from_=-1.0)
    assert e.value.field == "from_" and "--" not in str(e.value)
    with pytest.raises(InputError) as e:
        stickslip.branch("pmma", param="nu", max_steps=-3)
    assert e.value.field == "max_steps"


@pytest.fixture(scope="module")
def pmma_diagram():
    return stickslip.diagram("pmma")


def test_diagram_equals_the_cli_json(cli, pmma_diagram):
    expected = cli("diagram", "--scene", "pmma")
    assert _without(pmma_diagram.to_dict(), "files", "elapsed_s") == _without(expected, "files", "elapsed_s")
    d = pmma_diagram
    assert d.complete and d.to_dict()["files"] == []
    curve = d.to_dict()["hopf_curve"]
    assert d.nu.tolist() == [p["nu"] for p in curve] and d.kappa.dtype == np.float64
    assert set(d.criticality) <= {"supercritical", "subcritical", "degenerate"}
    assert "bautin" in list(d.special_points["kind"])


def test_diagram_is_appendix_c(pmma_diagram):
    # C11/C12 along the whole curve.
    d = pmma_diagram
    ok = d.kappa > 1e-6 * d.kappa.max()
    assert np.allclose(d.kappa[ok], d.kappa_appendix_c[ok], rtol=1e-8)


def test_diagram_partial_with_its_fold_curve(cli):
    # brockley: the curve of folds of cycles stops short (status 4).
    d = stickslip.diagram("brockley")
    expected = cli("diagram", "--scene", "brockley", expect=4)
    assert _without(d.to_dict(), "files", "elapsed_s") == _without(expected, "files", "elapsed_s")
    assert not d.complete and len(d.lpc_curve["nu"]) > 0


def test_diagram_in_a_pair_of_controls(cli):
    d = stickslip.diagram("pmma", x="V", y="K")
    expected = cli("diagram", "--scene", "pmma", "--x", "V", "--y", "K")
    assert _without(d.to_dict(), "files", "elapsed_s") == _without(expected, "files", "elapsed_s")
    assert len(d) > 10 and "x" in d.hopf_curve and "y" in d.hopf_curve


def test_diagram_figures_and_pickle(tmp_path, pmma_diagram):
    files = pmma_diagram.figures(tmp_path)
    names = sorted(p.rsplit("/", 1)[-1] for p in files)
    assert names == ["pmma-stability-dimensionless.png", "pmma-stability-dimensionless.svg",
                     "pmma-stability-physical.png", "pmma-stability-physical.svg"]
    back = pickle.loads(pickle.dumps(pmma_diagram))
    assert back == pmma_diagram
    # Read back from a pickle, the result draws its figures by computing them again.
    again = back.figures(tmp_path / "again")
    assert len(again) == 4
    assert stickslip.diagram("pmma", x="V", y="K").figures(tmp_path)[0].endswith(
        "pmma-stability-K-vs-V.png")


def test_diagram_errors_name_the_field():
    with pytest.raises(InputError) as e:
        stickslip.diagram("pmma", nu_range=(10, 1))
    assert e.value.field == "nu_range"
    with pytest.raises(InputError) as e:
        stickslip.diagram("pmma", x="V", y="K", x_range=(0, 1))
    assert e.value.field == "x_range"
    with pytest.raises(InputError) as e:
        stickslip.diagram("pmma", x="Vee")
    assert "V" in str(e.value)
