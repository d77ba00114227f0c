"""examples/python/cycles.py runs and draws its figure."""

import importlib.util
import subprocess
import sys


def test_example_runs(root, tmp_path):
    fig = tmp_path / "cycles.png"
    p = subprocess.run(
        [sys.executable, str(root / "examples" / "python" / "cycles.py"), str(fig)],
        capture_output=True, text=True, cwd=tmp_path,
    )
    assert p.returncode == 0, p.stderr
    assert "Hopf pmma" in p.stdout and "cycles" in p.stdout
    if importlib.util.find_spec("matplotlib"):
        assert fig.stat().st_size > 10_000


def test_notebook_runs(root, tmp_path):
    p = subprocess.run(
        [sys.executable, str(root / "examples" / "python" / "notebook.py"), str(tmp_path)],
        capture_output=True, text=True, cwd=tmp_path,
    )
    assert p.returncode == 0, p.stderr
    for line in ("<Hopf pmma", "<Branch pmma", "<Diagram pmma", "<Cycles pmma", "<Simulation pmma",
                 "sweep: 40 points"):
        assert line in p.stdout, p.stdout
    assert len(list(tmp_path.glob("*.png"))) >= 8
    if importlib.util.find_spec("matplotlib"):
        assert (tmp_path / "notebook.png").stat().st_size > 20_000
