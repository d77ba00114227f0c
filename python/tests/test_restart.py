"""Restarts from Python (issue 24): cycles(from_file=, index=) against the
command line's `cycles --from`; a Python run's orbits written with
orbits_file= and restarted from its saved to_dict(); branch(from_file=)
and hopf(from_file=) against the command line; the errors name the field."""

import json

import pytest

import stickslip
from stickslip import InputError


def _without_files(d):
    d = dict(d)
    for k in ("files", "orbits_file"):
        d.pop(k)
    return d


@pytest.fixture(scope="module")
def written(cli, tmp_path_factory):
    """A short PMMA branch of cycles from the command line, saved."""
    path = tmp_path_factory.mktemp("restart") / "pmma.json"
    d = cli("cycles", "--max-steps", "5", expect=4)
    path.write_text(json.dumps(d))
    return path, d


def test_cycles_restart_equals_the_cli(cli, written):
    path, first = written
    r = stickslip.cycles(from_file=path, index=3, max_steps=3)
    expected = cli("cycles", "--from", str(path), "--index", "3", "--max-steps", "3", expect=4)
    assert _without_files(r.to_dict()) == _without_files(expected)
    d = r.to_dict()
    assert d["start"]["kind"] == "restart" and d["start"]["label"] == 3
    stored = next(c for c in first["cycles"] if c["label"] == 3)
    restarted = next(c for c in d["cycles"] if c["label"] == 0)
    assert restarted["kappa"] == stored["kappa"]
    assert restarted["period"] == pytest.approx(stored["period"], rel=1e-14)
    assert d["source"] == first["source"]
    assert d["orbits_file"] is None


def test_a_python_run_restarts_with_orbits_file(tmp_path):
    orbits = tmp_path / "orbits.jsonl"
    r = stickslip.cycles(max_steps=5, orbits_file=orbits)
    d = r.to_dict()
    assert d["orbits_file"] == str(orbits.resolve())
    lines = orbits.read_text().splitlines()
    assert [json.loads(x)["label"] for x in lines] == [c["label"] for c in d["cycles"]]
    saved = tmp_path / "run.json"
    saved.write_text(json.dumps(d))
    again = stickslip.cycles(from_file=saved, index=2, max_steps=2).to_dict()
    stored = next(c for c in d["cycles"] if c["label"] == 2)
    first = next(c for c in again["cycles"] if c["label"] == 0)
    assert first["kappa"] == stored["kappa"]
    assert first["period"] == pytest.approx(stored["period"], rel=1e-14)


def test_a_run_without_orbits_file_cannot_be_restarted(tmp_path):
    d = stickslip.cycles(max_steps=2).to_dict()
    assert d["orbits_file"] is None
    saved = tmp_path / "run.json"
    saved.write_text(json.dumps(d))
    with pytest.raises(InputError) as e:
        stickslip.cycles(from_file=saved, index=0)
    assert "orbits_file" in str(e.value) and str(saved) in str(e.value)
    with pytest.raises(InputError) as e:
        stickslip.cycles(from_file=saved)
    assert "from_file and index go together" in str(e.value)


def test_branch_and_hopf_restart_equal_the_cli(cli, tmp_path):
    b = stickslip.branch(param="K", max_steps=10)
    saved = tmp_path / "branch.json"
    saved.write_text(json.dumps(b.to_dict()))
    again = stickslip.branch(from_file=saved, index=4, param="nu", to=2.0, max_steps=5)
    expected = cli("branch", "--from", str(saved), "--index", "4", "--param", "nu",
                   "--to", "2", "--max-steps", "5", expect=4)
    assert again.to_dict() == expected
    assert again.to_dict()["restarted_from"]["label"] == 4
    h = stickslip.hopf(from_file=saved, index=4).to_dict()
    assert h == cli("hopf", "--from", str(saved), "--index", "4")
    point = b.to_dict()["points"][4]
    direct = stickslip.hopf(stickslip.Scene.builtin("pmma").with_(kappa=point["kappa"])).to_dict()
    assert h["kappa_c"] == direct["kappa_c"]
    assert h["operating_point"] == direct["operating_point"]
    with pytest.raises(InputError):
        stickslip.branch(from_file=saved, index=4, from_=1.0)
    with pytest.raises(InputError) as e:
        stickslip.branch(from_file=saved, index=99)
    assert "labelled 0 to" in str(e.value)


def test_a_scene_beside_from_file_must_be_the_files(cli, tmp_path):
    """The file's run is of brockley: a scene named beside from_file, the
    default's name included, is refused naming `source.scene`; the file's
    own scene is accepted."""
    path = tmp_path / "brockley.json"
    path.write_text(json.dumps(cli("cycles", "--scene", "brockley", "--max-steps", "3", expect=4)))
    with pytest.raises(InputError) as e:
        stickslip.cycles("pmma", from_file=path, index=1, max_steps=1)
    assert e.value.field == "source.scene"
    with pytest.raises(InputError) as e:
        stickslip.hopf("pmma", from_file=path, index=1)
    assert e.value.field == "source.scene"
    d = stickslip.cycles("brockley", from_file=path, index=1, max_steps=1).to_dict()
    assert d["start"]["label"] == 1
