"""`stickslip.sweep`: one job over a grid of scenes, in chunks, on local
worker threads or a Dask cluster, into one table with a row per point."""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import os
import threading
from concurrent.futures import ThreadPoolExecutor, as_completed
from typing import Any, Callable, Iterable, Mapping, Sequence

import numpy as np

#: The jobs a sweep runs, by name.
JOBS = ("hopf", "diagram", "cycles")

#: The columns every table starts with (after the grid's own columns).
STATUS_COLUMNS = ("status", "message")


def _grid(grid: Any, scene: Any) -> tuple[Any, list[str], list[Any]]:
    """The base scene, the grid's columns, and the points: override dicts
    (applied to the base) or scenes."""
    from . import Scene, _scene, InputError

    if isinstance(grid, Mapping):
        names = list(grid)
        values = []
        for name in names:
            v = grid[name]
            if isinstance(v, (str, bytes)) or not isinstance(v, Iterable):
                v = [v]
            values.append([x.item() if isinstance(x, np.generic) else x for x in v])
        points = [dict(zip(names, combo)) for combo in itertools.product(*values)]
        return _scene(scene), names, points
    grid = list(grid)
    if all(isinstance(p, Scene) for p in grid):
        if scene is not None:
            raise InputError("grid is a list of scenes: leave out scene=", "scene")
        return None, ["scene"], grid
    if all(isinstance(p, Mapping) for p in grid):
        names: list[str] = []
        for p in grid:
            names.extend(k for k in p if k not in names)
        return _scene(scene), names, [dict(p) for p in grid]
    raise InputError(
        "grid: expected a dict of override name to values, a list of override dicts, "
        "or a list of scenes",
        "grid",
    )


def _flat(d: Mapping[str, Any], row: dict, prefix: str = "") -> dict:
    """The scalar fields of a record into `row`, nested names joined by
    dots; a list as its length (`n_<name>`)."""
    for k, v in d.items():
        if type(v) is dict:
            _flat(v, row, f"{prefix}{k}.")
        elif type(v) is list:
            row[f"{prefix}n_{k}"] = len(v)
        elif k != "elapsed_s":
            row[prefix + k] = v
    return row


def _summary(job: str, result: Any) -> dict[str, Any]:
    """A result as one row of scalars."""
    # The record as parsed (read only here; to_dict() would copy it).
    row = _flat(result._data, {})
    if job == "cycles" and len(result):
        t = result.table
        for col in ("kappa", "K_N_per_m", "delta_s_N", "period_s"):
            if col in t and t[col].dtype.kind == "f" and np.isfinite(t[col]).any():
                row[f"{col}_min"] = float(np.nanmin(t[col]))
                row[f"{col}_max"] = float(np.nanmax(t[col]))
    return row


def _run_chunk(job: str, base: dict | None, items: list, options: dict,
               stop: threading.Event | None = None) -> list[dict] | None:
    """Runs `job` at the points `items` (`(index, overrides or scene)`):
    a row per point, a failure recorded in it; None when `stop` is set
    before the chunk is done (an interrupted sweep keeps whole chunks)."""
    from . import Scene, InputError, NumericalError, cycles, diagram, hopf

    function: Callable = {"hopf": hopf, "diagram": diagram, "cycles": cycles}[job]
    base_scene = None
    if base is not None:
        base_scene = Scene.__new__(Scene)
        base_scene._init(base["builtin"], base["toml"], base["origin"], base["stem"],
                         base["set"], check=False)
    rows = []
    for index, item in items:
        if stop is not None and stop.is_set():
            return None
        row: dict[str, Any] = {"point": index}
        summary: dict[str, Any] = {}
        try:
            s = item if isinstance(item, Scene) else base_scene._with_unchecked(item)
            result = function(s, **options)
            if getattr(result, "interrupted", False):
                # Ctrl-C stopped the job: it stops the sweep (the chunk is not kept).
                raise KeyboardInterrupt
            complete = result.complete
            row["status"] = "ok" if complete else "partial"
            row["message"] = None if complete else result.stop
            summary = _summary(job, result)
        except InputError as e:
            row["status"], row["message"] = "input_error", str(e)
        except NumericalError as e:
            row["status"], row["message"] = "numerical_error", str(e)
            if e.partial is not None:
                summary = _summary(job, e.partial)
        except Exception as e:  # a point's failure is recorded, not fatal
            row["status"], row["message"] = "error", f"{type(e).__name__}: {e}"
        for k, v in summary.items():
            row[k if k not in row else f"result.{k}"] = v
        rows.append(row)
    return rows


def _fingerprint(job, base, points, options, chunk) -> str:
    from . import Scene

    def item(p):
        return p.__getstate__() if isinstance(p, Scene) else p

    text = json.dumps(
        [job, base, [item(p) for p in points], options, chunk],
        sort_keys=True, default=repr,
    )
    return hashlib.sha256(text.encode()).hexdigest()


def _plain(x: Any) -> Any:
    """A numpy scalar as a Python one (for JSON)."""
    if isinstance(x, np.generic):
        return x.item()
    raise TypeError(f"not JSON: {type(x).__name__}")


class _Store:
    """`out=`: a directory with the sweep's manifest and a file per
    finished chunk (`chunk-00012.json`, written whole or not at all)."""

    def __init__(self, out, fingerprint: str, job: str, n: int, chunk: int):
        from . import InputError

        self.dir = os.fspath(out)
        os.makedirs(self.dir, exist_ok=True)
        manifest = os.path.join(self.dir, "manifest.json")
        mine = {"job": job, "points": n, "chunk": chunk, "fingerprint": fingerprint}
        if os.path.exists(manifest):
            with open(manifest, encoding="utf-8") as f:
                theirs = json.load(f)
            if theirs != mine:
                raise InputError(
                    f"out = {self.dir} holds another sweep ({theirs.get('job')}, "
                    f"{theirs.get('points')} points, chunk {theirs.get('chunk')}, other "
                    "points or options): give another directory, or remove it to start over",
                    "out",
                )
        else:
            self._write(manifest, mine)

    def path(self, k: int) -> str:
        return os.path.join(self.dir, f"chunk-{k:05d}.json")

    def load(self, k: int) -> list[dict] | None:
        try:
            with open(self.path(k), encoding="utf-8") as f:
                return json.load(f)["rows"]
        except (OSError, ValueError, KeyError):
            return None

    def save(self, k: int, rows: list[dict]) -> None:
        self._write(self.path(k), {"chunk": k, "rows": rows})

    @staticmethod
    def _write(path: str, value: Any) -> None:
        tmp = f"{path}.{os.getpid()}.tmp"
        with open(tmp, "w", encoding="utf-8") as f:
            json.dump(value, f, default=_plain)
        os.replace(tmp, path)


def _table(rows: list[dict], grid_columns: Sequence[str]):
    """One table, a row per point: pandas where installed, else a numpy
    structured array."""
    from . import _column

    rows = sorted(rows, key=lambda r: r["point"])
    columns = ["point", *grid_columns, *STATUS_COLUMNS]
    seen = set(columns)
    for r in rows:
        for k in r:
            if k not in seen:
                seen.add(k)
                columns.append(k)
    try:
        import pandas as pd
    except ImportError:
        arrays = [_column([r.get(c) for r in rows]) for c in columns]
        out = np.empty(len(rows), dtype=[(c, a.dtype) for c, a in zip(columns, arrays)])
        for c, a in zip(columns, arrays):
            out[c] = a
        return out
    return pd.DataFrame.from_records(rows, columns=columns)


def sweep(
    job: str,
    grid: Mapping[str, Any] | Sequence[Mapping[str, Any]] | Sequence[Any],
    scene: Any = None,
    client: Any = None,
    chunk: int | None = None,
    out: str | os.PathLike | None = None,
    *,
    workers: int | None = None,
    **options: Any,
):
    """Runs `job` ("hopf", "diagram" or "cycles", options as for that
    function) over `grid` in chunks, and returns one table with a row per
    point (a pandas DataFrame where pandas is installed, else a numpy
    structured array).

    grid: a dict of override name to values (`{"K": [1e5, 2e5], "V": [1,
        10]}`: their Cartesian product, applied to `scene` with `with_`),
        a list of override dicts, or a list of scenes.
    scene: the scene the overrides apply to (default: pmma).
    client: a `dask.distributed.Client`: the chunks run on its workers
        (a `LocalCluster`, or a SLURM cluster through dask-jobqueue);
        default: `workers` threads of this process (default: the number of
        CPUs; `workers=0` runs in the calling thread). The jobs release
        the GIL, so the threads compute in parallel, and a script needs no
        `if __name__ == "__main__":` guard.
    chunk: points per chunk (default: about four chunks per worker, at
        most 1000 points).
    out: a directory: each chunk's rows are written there as it finishes
        (`chunk-00000.json`, ...), and a rerun with the same arguments
        skips the chunks already written (an interrupted sweep resumes).

    The table's columns: `point` (the index in the grid), the grid's
    names (or `scene`, the scene's label), `status` (ok, partial,
    input_error, numerical_error, error) and `message`, then the result's
    scalar fields as in its `to_dict()` (nested names joined by dots:
    `physical.K_N_per_m`; lists as their length, `n_cycles`; a field
    named as a column before it prefixed `result.`). A failed point is a
    row with its status, never an exception.
    """
    from . import InputError, Scene

    if job not in JOBS:
        raise InputError(f"job = {job!r}: expected one of {', '.join(JOBS)}", "job")
    base_scene, grid_columns, points = _grid(grid, scene)
    base = None if base_scene is None else base_scene.__getstate__()
    n = len(points)
    if client is not None:
        n_workers = max(1, len(client.scheduler_info().get("workers", {})))
    else:
        n_workers = (os.cpu_count() or 1) if workers is None else int(workers)
    if chunk is None:
        chunk = max(1, min(1000, math.ceil(n / (4 * max(1, n_workers)))))
    elif isinstance(chunk, bool) or not isinstance(chunk, (int, np.integer)) or chunk < 1:
        raise InputError(f"chunk = {chunk!r}: expected an integer >= 1", "chunk")
    chunk = int(chunk)
    chunks = [list(enumerate(points))[k:k + chunk] for k in range(0, n, chunk)]
    labels = {}
    for i, p in enumerate(points):
        labels[i] = {"scene": p.label} if isinstance(p, Scene) else {
            c: p.get(c) for c in grid_columns}
    store = None
    if out is not None:
        store = _Store(out, _fingerprint(job, base, points, options, chunk), job, n, chunk)
    rows: list[dict] = []
    todo = []
    for k in range(len(chunks)):
        done = store.load(k) if store else None
        if done is None:
            todo.append(k)
        else:
            rows.extend(done)

    def finished(k: int, chunk_rows: list[dict]) -> None:
        for r in chunk_rows:
            label = labels[r["point"]]
            for c in grid_columns:
                r.setdefault(c, label.get(c))
        if store:
            store.save(k, chunk_rows)
        rows.extend(chunk_rows)

    if todo and client is not None:
        from distributed import as_completed as dask_completed

        futures = {}
        for k in todo:
            f = client.submit(_run_chunk, job, base, chunks[k], options, pure=False)
            futures[f.key] = (k, f)
        try:
            for f in dask_completed([f for _, f in futures.values()]):
                finished(futures[f.key][0], f.result())
        except BaseException:
            client.cancel([f for _, f in futures.values()])
            raise
    elif todo and (n_workers <= 1 or len(todo) == 1):
        for k in todo:
            finished(k, _run_chunk(job, base, chunks[k], options))
    elif todo:
        stop = threading.Event()
        pool = ThreadPoolExecutor(max_workers=min(n_workers, len(todo)))
        try:
            futures = {pool.submit(_run_chunk, job, base, chunks[k], options, stop): k
                       for k in todo}
            for f in as_completed(futures):
                finished(futures.pop(f), f.result())
        except BaseException:
            # Ctrl-C: the workers stop at their next point; the chunks they
            # finished meanwhile are kept too.
            stop.set()
            pool.shutdown(wait=True, cancel_futures=True)
            for f, k in futures.items():
                if f.done() and not f.cancelled() and f.exception() is None \
                        and f.result() is not None:
                    finished(k, f.result())
            raise
        pool.shutdown()
    for r in rows:
        label = labels[r["point"]]
        for c in grid_columns:
            r.setdefault(c, label.get(c))
    return _table(rows, grid_columns)
