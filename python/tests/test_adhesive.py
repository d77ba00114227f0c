"""Adhesive scenes (law = "adhesive", docs/model.md "Soft adhesive
contacts") through the Python package: the same jobs as the command line,
the same JSON."""

import pytest

import stickslip
from stickslip import InputError, Scene


def _without_timing(d: dict) -> dict:
    return {k: v for k, v in d.items() if k not in ("elapsed_s", "files")}


@pytest.mark.parametrize("command", ["hopf", "branch", "diagram"])
def test_the_gel_scene_equals_the_cli_json(cli, command):
    result = getattr(stickslip, command)("gel")
    assert isinstance(result, stickslip.Adhesive)
    extra = ["--param", "V"] if command == "branch" else []
    expected = cli(command, "--scene", "gel", *extra)
    assert _without_timing(result.to_dict()) == _without_timing(expected)


def test_overrides_and_cycles_and_simulate(cli):
    gel = Scene.builtin("gel").with_(K=500)
    h = stickslip.hopf(gel)
    assert h["params"]["kappa"] == pytest.approx(500 * 0.025e-6 / 0.05, rel=1e-14)
    assert h == stickslip.hopf(gel)
    c = stickslip.cycles("gel")
    expected = cli("cycles", "--scene", "gel")
    assert _without_timing(c.to_dict()) == _without_timing(expected)
    assert c.complete
    s = stickslip.simulate("gel", protocol=[(200, 20), (0, 1), (200, 10)], perturb=0.0)
    assert s["complete"]


def test_options_without_meaning_are_refused_by_name():
    with pytest.raises(InputError) as e:
        stickslip.cycles("gel", at_kappa=1e-3)
    assert e.value.field == "at_kappa", e.value
    with pytest.raises(InputError) as e:
        stickslip.hopf("gel", param="V")
    assert "adhesive" in str(e.value)
    with pytest.raises(InputError) as e:
        stickslip.hopf(Scene.builtin("gel").with_(tau_on=-1))
    assert "tau_on" in str(e.value)
