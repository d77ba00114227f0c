"""The examples run: examples/python/ and the README's."""

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


def readme_example(root) -> str:
    """The code of the README's section "From Python"."""
    readme = (root / "README.md").read_text()
    section = readme[readme.index("## From Python"):]
    code = section[section.index("```python\n") + len("```python\n"):]
    return code[:code.index("```")]


def test_the_readme_example_runs_as_a_script(root, tmp_path):
    """The README's "From Python" example, saved as a file and run as a
    script (no `if __name__ == "__main__":` guard): its sweep included."""
    code = readme_example(root)
    script = tmp_path / "example.py"
    script.write_text(code + "\nprint(len(t), sorted({str(s) for s in t['status']}))\n")
    done = subprocess.run([sys.executable, str(script)], cwd=tmp_path,
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split()[-2:] == ["9", "['ok']"], done.stdout
    assert list((tmp_path / "out").glob("*-stability-physical.png"))


def test_pip_install_in_a_fresh_environment(root, tmp_path):
    """`pip install ./python` into a new virtual environment (build
    isolation: maturin and numpy from the package registry; the core's
    build reuses the workspace's target directory), then the README's
    example in that environment, which has neither pandas nor dask."""
    env_dir = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(env_dir)], check=True)
    python = env_dir / "bin" / "python"
    install = subprocess.run(
        [str(python), "-m", "pip", "install", "--quiet", "--disable-pip-version-check",
         str(root / "python")],
        capture_output=True, text=True, timeout=1800)
    assert install.returncode == 0, install.stderr[-3000:]
    code = readme_example(root)
    script = tmp_path / "example.py"
    script.write_text(code + "\nprint(type(t).__name__, len(t), sorted({str(s) for s in t['status']}))\n")
    done = subprocess.run([str(python), str(script)], cwd=tmp_path,
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split()[-3:] == ["ndarray", "9", "['ok']"], done.stdout
