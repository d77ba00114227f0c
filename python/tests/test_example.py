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
