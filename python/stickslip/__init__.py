"""stickslip from Python: the stick-slip onset of a block pulled through a
spring across a rate-and-state frictional interface, its type, steady
sliding across it, the stability diagram, the stick-slip cycles and
simulations in time, each job one call returning a result object; sweeps
of a job over a grid on worker threads or a Dask cluster.

    >>> import stickslip
    >>> scene = stickslip.Scene.builtin("pmma").with_(K=2e5)
    >>> h = stickslip.hopf(scene)
    >>> h.kappa_c, h.criticality
    >>> b = stickslip.branch(scene, param="nu")            # steady sliding in velocity
    >>> d = stickslip.diagram(scene); d.figures("out")     # the stability diagram
    >>> c = stickslip.cycles(scene, kappa_fraction=0.9)
    >>> c.kappa, c.delta_s          # numpy arrays, one entry per cycle
    >>> s = stickslip.simulate(scene, protocol=[(1.0, 300.0)])
    >>> s.t_s, s.spring_force_N, s.regime
    >>> stickslip.sweep("hopf", {"K": [1e5, 2e5], "V": [0.1, 1, 10]})

Every result has `.to_dict()` (exactly what `stickslip <command> --json`
prints for the same request), `.complete`, `.stop`, `.to_pandas()` (with
pandas installed), and pickles. Bad input raises `InputError` (a
`ValueError`) naming the field; a numerical failure raises `NumericalError`
with the result computed before it as `.partial`. The GIL is released while
a job computes; Ctrl-C stops a branch, a branch of cycles or a simulation
and returns what was computed so far with `complete = False`.

Units: dimensionless as in docs/model.md (kappa = K D0/W, nu = V/V0, ...),
with the physical values beside them in the fields named with their unit
(`K_N_per_m`, `period_s`, ...), as in the command line's JSON.
"""

from __future__ import annotations

import copy
import json
import os
from typing import Any, Iterable, Mapping, Sequence

import numpy as np

from . import _native
from ._errors import InputError, NumericalError

__all__ = [
    "Scene",
    "scenes",
    "hopf",
    "branch",
    "diagram",
    "cycles",
    "simulate",
    "fit",
    "sweep",
    "Hopf",
    "Adhesive",
    "Branch",
    "Diagram",
    "Cycles",
    "Simulation",
    "Fit",
    "InputError",
    "NumericalError",
    "DEFAULT_INERTIA_THRESHOLD",
]

#: Inertia is dropped (quasi-static model) when m nu^2 / mu_v is below this.
DEFAULT_INERTIA_THRESHOLD: float = _native.DEFAULT_INERTIA_THRESHOLD

#: The scene used when none is given.
DEFAULT_SCENE = "pmma"


def scenes() -> dict[str, str]:
    """The built-in scenes: name -> one-line description."""
    return dict(_native.scenes())


def _toml_value(key: str, value: Any) -> str:
    if isinstance(value, bool):
        raise InputError(f"{key} = {value!r}: expected a number, not a boolean", key)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, (int, float, np.integer, np.floating)):
        x = float(value)
        if x != x or x in (float("inf"), float("-inf")):
            return {"nan": "nan"}.get(repr(x), "inf" if x > 0 else "-inf")
        return repr(int(value)) if isinstance(value, (int, np.integer)) else repr(x)
    if isinstance(value, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_toml_value(key, v) for v in value) + "]"
    raise InputError(
        f"{key} = {value!r}: expected a number, a string or a list of numbers", key
    )


def _override(name: str, value: Any) -> str:
    """One `--set` item `NAME=VALUE`; `V_range` takes a pair (LO, HI)."""
    if isinstance(value, (list, tuple, np.ndarray)):
        if len(value) != 2:
            raise InputError(f"{name} = {value!r}: expected a pair (LO, HI)", name)
        return f"{name}={float(value[0])!r}:{float(value[1])!r}"
    if isinstance(value, str):
        return f"{name}={value}"
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InputError(f"{name} = {value!r}: expected a number", name)
    return f"{name}={float(value)!r}"


class Scene:
    """A physical experiment: the friction law, the block, the spring and the
    driving, in laboratory units (a scene file, docs/model.md), with
    overrides. Make one with `Scene.builtin(name)`, `Scene.from_toml(path)`
    or `Scene(A=..., B=..., D0=..., ...)` (the scene file's keys: name,
    description, A, B, mu0, mu2, mu_vv, mu_vphi (the coefficients of
    (ln v)^2 and (ln theta)(ln v), docs/model.md), tau [s], eta [s/m]
    (radiation damping, docs/model.md), state_law
    ("ageing" or "slip"), D0 [µm], V0 [µm/s], M [kg], W [N], g [m/s^2],
    K [N/m], V [µm/s], V_range [µm/s, a pair]); change it with
    `scene.with_(K=2e5, nu=3)` (the names `--set` takes). Scenes are
    immutable, compare equal when made the same way, and pickle.
    """

    def __init__(self, **keys: Any):
        if not keys:
            raise InputError(
                "Scene(**keys) needs the scene file's keys (at least A); "
                "for a built-in scene use Scene.builtin(name)",
                "A",
            )
        lines = [f"{k} = {_toml_value(k, v)}" for k, v in keys.items()]
        self._init(None, "\n".join(lines) + "\n", "Scene(**keys)", "custom", ())

    def _init(self, builtin, toml, origin, stem, overrides, check: bool = True) -> None:
        self._builtin: str | None = builtin
        self._toml: str | None = toml
        self._origin: str = origin
        self._stem: str = stem
        self._set: tuple[str, ...] = tuple(overrides)
        self._info_cache: dict | None = _native.setup(self._arg()) if check else None

    @property
    def _info(self) -> dict:
        if self._info_cache is None:
            self._info_cache = _native.setup(self._arg())
        return self._info_cache

    @classmethod
    def _make(cls, builtin, toml, origin, stem, overrides=()) -> "Scene":
        s = cls.__new__(cls)
        s._init(builtin, toml, origin, stem, overrides)
        return s

    @classmethod
    def builtin(cls, name: str = DEFAULT_SCENE) -> "Scene":
        """A built-in scene by name (`stickslip.scenes()` lists them)."""
        if name not in scenes():
            # The error of the command line, with a suggestion.
            _native.builtin_toml(name)
        return cls._make(name, None, name, name)

    @classmethod
    def from_toml(cls, path: str | os.PathLike) -> "Scene":
        """A scene file: its text is read now and kept (the scene does not
        depend on the file afterwards). Without a `name` key the scene is
        named after the file's stem."""
        path = os.fspath(path)
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except OSError as e:
            raise InputError(f"cannot read scene file {path}: {e.strerror}", path) from None
        stem = os.path.splitext(os.path.basename(path))[0] or "scene"
        return cls._make(None, text, path, stem)

    @classmethod
    def from_toml_text(cls, text: str, name: str = "custom") -> "Scene":
        """A scene from the text of a scene file (`name` if it has no `name` key)."""
        return cls._make(None, text, name, name)

    def _with_unchecked(self, overrides: Mapping[str, Any]) -> "Scene":
        """`with_` without setting the scene up now (a sweep's points: the
        job checks them, and a bad one is that point's error)."""
        items = dict(item.split("=", 1) for item in self._set)
        for name, value in overrides.items():
            items.pop(name, None)
            items[name] = _override(name, value).split("=", 1)[1]
        s = Scene.__new__(Scene)
        s._init(self._builtin, self._toml, self._origin, self._stem,
                [f"{k}={v}" for k, v in items.items()], check=False)
        return s

    def with_(self, **overrides: Any) -> "Scene":
        """This scene with overrides, named as `--set` takes them: the scene
        keys in their units (K [N/m], M [kg], W [N], V [µm/s], tau [s], D0
        [µm], V0 [µm/s], g [m/s^2], eta [s/m], V_range=(LO, HI) [µm/s], state_law=
        "ageing" or "slip") or the dimensionless parameters (kappa, nu, m,
        A, B, mu0, mu2, theta_c, mu_vv, mu_vphi, eta_d).
        A name given again replaces its earlier value."""
        items = dict(item.split("=", 1) for item in self._set)
        for name, value in overrides.items():
            items.pop(name, None)
            items[name] = _override(name, value).split("=", 1)[1]
        return Scene._make(
            self._builtin,
            self._toml,
            self._origin,
            self._stem,
            [f"{k}={v}" for k, v in items.items()],
        )

    def to_toml(self) -> str:
        """The scene file: the scene's text with the physical overrides
        written as its keys. Dimensionless overrides (kappa=..., nu=...)
        are no scene keys: they follow as a comment, and a scene read back
        from the text lacks them (pickle keeps them)."""
        text, dimensionless = _native.scene_toml(self._arg())
        if dimensionless:
            text += (
                "\n# dimensionless overrides, not scene keys (Scene.with_): "
                + ", ".join(dimensionless)
                + "\n"
            )
        return text

    @property
    def name(self) -> str:
        """The scene's name (the `name` key, else the file's stem)."""
        return self._info["name"]

    @property
    def description(self) -> str:
        return self._info["description"]

    @property
    def label(self) -> str:
        """The name with the overrides: `pmma (K=200000)`."""
        return self._info["label"]

    @property
    def overrides(self) -> tuple[str, ...]:
        """The overrides as `--set` items, `NAME=VALUE`."""
        return self._set

    @property
    def params(self) -> dict[str, float | str]:
        """The dimensionless parameters (docs/model.md), overrides applied."""
        return dict(self._info["params"])

    @property
    def units(self) -> dict[str, Any]:
        """The scales: D0 [µm], V0 [µm/s], M [kg], W [N], V_range [µm/s]."""
        return {
            k: self._info[k]
            for k in ("D0_um", "V0_um_per_s", "M_kg", "W_N", "V_range_um_per_s")
        }

    @property
    def model(self) -> str:
        """The model chosen for the scene's own velocity (inertial or quasi-static)."""
        return self._info["model"]

    def _arg(self, model: str | None = None, inertia_threshold: float | None = None) -> dict:
        return {
            "builtin": self._builtin,
            "toml": self._toml,
            "origin": self._origin,
            "stem": self._stem,
            "set": list(self._set),
            "model": model,
            "inertia_threshold": DEFAULT_INERTIA_THRESHOLD
            if inertia_threshold is None
            else float(inertia_threshold),
        }

    def _key(self):
        return (self._builtin, self._toml, self._origin, self._stem, self._set)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Scene) and self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())

    def __getstate__(self):
        return {
            "builtin": self._builtin,
            "toml": self._toml,
            "origin": self._origin,
            "stem": self._stem,
            "set": self._set,
        }

    def __setstate__(self, state):
        self._init(state["builtin"], state["toml"], state["origin"], state["stem"], state["set"])

    def __repr__(self) -> str:
        if self._builtin is not None:
            base = f"Scene.builtin({self._builtin!r})"
        elif self._origin == "Scene(**keys)":
            base = f"Scene(<keys of {self.name!r}>)"
        else:
            base = f"Scene.from_toml({self._origin!r})"
        if self._set:
            args = ", ".join(_repr_override(s) for s in self._set)
            base += f".with_({args})"
        return base


def _repr_override(item: str) -> str:
    name, value = item.split("=", 1)
    if ":" in value:
        lo, hi = value.split(":", 1)
        return f"{name}=({lo}, {hi})"
    return f"{name}={value}"


def _scene(scene: Scene | str | os.PathLike | None) -> Scene:
    if scene is None:
        return Scene.builtin(DEFAULT_SCENE)
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, (str, os.PathLike)):
        name = os.fspath(scene)
        if name in scenes():
            return Scene.builtin(name)
        return Scene.from_toml(name)
    raise TypeError(f"scene: expected a Scene, a built-in name or a path, not {type(scene).__name__}")


def _scene_arg(scene, from_file, model: str | None, inertia_threshold: float | None) -> dict:
    """The scene options of a job: those of `scene`, or with `from_file`
    and no scene, none (a restart takes the file's scene and refuses any
    other, the default's name included)."""
    if from_file is None or scene is not None:
        return _scene(scene)._arg(model, inertia_threshold)
    arg = Scene.builtin(DEFAULT_SCENE)._arg(model, inertia_threshold)
    arg["builtin"] = ""
    return arg


def _column(values: Sequence[Any]) -> np.ndarray:
    """A JSON column as a numpy array: numbers as float64 (null as NaN),
    integers as int64, booleans as bool (with a null: an object array of
    True, False, None), strings as str."""
    present = [v for v in values if v is not None]
    if not present:
        return np.full(len(values), np.nan)
    if all(isinstance(v, bool) for v in present):
        if len(present) == len(values):
            return np.array(values, dtype=bool)
        return np.array(values, dtype=object)
    if all(isinstance(v, int) and not isinstance(v, bool) for v in present) and len(
        present
    ) == len(values):
        return np.array(values, dtype=np.int64)
    if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in present):
        return np.array([np.nan if v is None else v for v in values], dtype=np.float64)
    if all(isinstance(v, str) for v in present):
        return np.array(["" if v is None else v for v in values], dtype=str)
    return np.array(values, dtype=object)


def _table(rows: Sequence[Mapping[str, Any]], columns: Iterable[str] | None = None) -> dict[str, np.ndarray]:
    """The scalar fields of `rows` (or `columns`), one numpy array each."""
    if columns is None:
        columns = []
        for r in rows:
            columns.extend(
                k for k, v in r.items()
                if k not in columns and not isinstance(v, (list, dict))
            )
    return {c: _column([r.get(c) for r in rows]) for c in columns}


class _Result:
    """A job's result: its record (the command's JSON) and its columns."""

    _data: dict

    def to_dict(self) -> dict:
        """The command line's JSON for the same request (`files` empty: no
        files are written)."""
        return copy.deepcopy(self._data)

    def to_json(self, indent: int | None = 2) -> str:
        return json.dumps(self._data, indent=indent)

    def __getitem__(self, key: str) -> Any:
        """A field of the JSON, as `to_dict()[key]`."""
        return self._data[key]

    @property
    def complete(self) -> bool:
        """Everything requested was delivered (the JSON's `complete`)."""
        return self._data["complete"]

    @property
    def stop(self) -> str | None:
        """Why the job ended short of the request, or how it ended, in
        words (the JSON's `stop`)."""
        return self._data["stop"]

    def __eq__(self, other: object) -> bool:
        return type(self) is type(other) and self._data == other._data  # type: ignore[attr-defined]

    __hash__ = None  # type: ignore[assignment]


class Adhesive(_Result):
    """A job's result on an adhesive scene (`law = "adhesive"`: a gel or an
    elastomer on glass, Schallamach's bonds, docs/model.md "Soft adhesive
    contacts"): the command line's JSON (`to_dict()`, `result["key"]`),
    no files written. `hopf`, `branch`, `diagram`, `cycles` and `simulate`
    return it for such a scene."""

    def __init__(self, data: dict):
        self._data = data

    @property
    def complete(self) -> bool:
        """Everything requested was delivered."""
        return bool(self._data.get("complete", True))

    @property
    def stop(self) -> str | None:
        """Why the job ended short of the request, if it did."""
        return self._data.get("stop")


def _adhesive(command: str, arg: Any, given: dict, **job: Any) -> Adhesive | None:
    """`command` on the scene of `arg` when it is adhesive, else `None`.
    The options in `given` that have a value have no meaning there: refused
    by name, as the command line refuses them."""
    if _native.law(arg) != "adhesive":
        return None
    for name, value in given.items():
        if value is not None and value is not False:
            raise InputError(
                f"{name} is not available on an adhesive scene: the adhesive block runs with "
                "its scene's values (docs/model.md, \"Soft adhesive contacts\")",
                name,
            )
    return Adhesive(json.loads(_native.adhesive(arg, command, **job)))


class _Columns:
    """Attribute access to a result's columns (the arrays in `_table_attr`),
    then to the fields of its JSON; `_hidden` names are neither."""

    _table_attr = "table"
    _hidden: tuple = ()

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_") or name == self._table_attr or name in self._hidden:
            raise AttributeError(name)
        table = self.__dict__.get(self._table_attr, {})
        if name in table:
            return table[name]
        data = self.__dict__.get("_data", {})
        if name in data:
            return copy.deepcopy(data[name])
        raise AttributeError(f"'{type(self).__name__}' has no attribute {name!r}")

    def __dir__(self):
        table = self.__dict__.get(self._table_attr, {})
        return sorted(set(super().__dir__()) | set(table) | set(self._data))


class _Drawn(_Result):
    """A result with the command line's figures (`figures(out_dir)`)."""

    #: The native drawing of the figures (not pickled).
    _handle: Any = None
    #: How the result was asked: (function name, scene, keyword options).
    _request: tuple | None = None

    def _set_request(self, handle, function: str, scene: "Scene | str | None", options: dict) -> None:
        self._handle = handle
        self._request = (function, scene, dict(options))

    def figures(self, out_dir: str | os.PathLike = ".") -> list[str]:
        """Writes the figures the command line draws for this result (PNG
        and SVG) into `out_dir` (created), named as the command names them
        (`<scene>_<overrides>-...`); returns the paths. A result read back
        from a pickle computes its job once more to draw them."""
        if self._handle is None:
            if self._request is None:
                raise RuntimeError("this result holds no figures (it was not computed by a job)")
            function, scene, options = self._request
            try:
                again = globals()[function](scene, **options)
            except NumericalError as e:
                again = e.partial
            self._handle = again._handle
        return [os.fspath(p) for p in self._handle.write(os.fspath(out_dir))]


class Hopf(_Result):
    """The stick-slip onset of a scene (`stickslip.hopf`): the critical
    stiffness and frequency, next to Appendix C, the onset type (first
    Lyapunov coefficient l1 with its rounding bound), the rig's operating
    point, and with `param` the critical value of that control parameter.
    The fields are the JSON's (`to_dict()`); the usual ones are attributes.
    """

    def __init__(self, data: dict, note: str | None = None):
        self._data = data
        #: Why the scene's own stiffness is not the onset's (it is compared with it).
        self.note = note

    @property
    def status(self) -> str:
        """`hopf` (an onset found) or `stable_for_all_stiffness`."""
        return self._data["status"]

    @property
    def stop(self) -> str:
        return self.status

    @property
    def found(self) -> bool:
        return self.status == "hopf"

    def _onset(self, key: str) -> Any:
        return self._data.get(key) if self.found else None

    @property
    def kappa_c(self) -> float | None:
        """Critical stiffness kappa_c = K_c D0 / W (None: no onset)."""
        return self._onset("kappa_c")

    @property
    def omega_c(self) -> float | None:
        """Angular frequency at onset [V0/D0]."""
        return self._onset("omega_c")

    @property
    def K_c(self) -> float | None:
        """Critical stiffness [N/m]."""
        p = self._onset("physical")
        return p["K_N_per_m"] if p else None

    @property
    def l1(self) -> float | None:
        """First Lyapunov coefficient (docs/model.md's convention)."""
        return self._onset("l1")

    @property
    def l1_error_bound(self) -> float | None:
        return self._onset("l1_error_bound")

    @property
    def criticality(self) -> str | None:
        """supercritical (continuous onset), subcritical (hysteretic) or degenerate."""
        return self._onset("criticality")

    @property
    def appendix_c(self) -> dict | None:
        """Appendix C's closed forms (C11/C12, C13) and the relative differences."""
        return copy.deepcopy(self._onset("appendix_c"))

    @property
    def model(self) -> str:
        return self._data["model"]

    @property
    def params(self) -> dict:
        return dict(self._data["params"])

    @property
    def operating_point(self) -> dict | None:
        return copy.deepcopy(self._data.get("operating_point"))

    @property
    def critical(self) -> dict | None:
        """With `param`: the onset in that control parameter."""
        return copy.deepcopy(self._data.get("critical"))

    def to_pandas(self):
        """The record flattened into one row (pandas.json_normalize)."""
        import pandas as pd

        return pd.json_normalize(self._data)

    def __reduce__(self):
        return (Hopf, (self._data, self.note))

    def __repr__(self) -> str:
        if self.found:
            return (
                f"<Hopf {self._data['scene']} ({self.model}): kappa_c = {self.kappa_c:.10e}, "
                f"K_c = {self.K_c:.6e} N/m, omega_c = {self.omega_c:.6e}, "
                f"{self.criticality} (l1 = {self.l1:.4e})>"
            )
        return f"<Hopf {self._data['scene']} ({self.model}): {self.status}>"


class Cycles(_Columns, _Drawn):
    """The stick-slip cycles of a scene (`stickslip.cycles`): the branch born
    at the Hopf point (or reached from a simulated orbit), continued in the
    stiffness, with its bifurcations and the cycles at requested
    stiffnesses.

    Column data are numpy arrays, one entry per cycle (in the order the
    JSON lists them): every scalar column of the cycles table (`-cycles.csv`)
    is an attribute (`kappa`, `period`, `delta_s`, `s_min`, ..., `K_N_per_m`,
    `period_s`, `delta_s_N`; `stable` is True/False/None where undecidable),
    `table` holds them all, `orbits[i]` is cycle i sampled over one period
    (columns t/T, s, v, theta; `orbit(i)` names them). `special_points`,
    `requested_points` and `lpc_curve` are tables of their own;
    `operating_point` is the cycle at the scene's own K, where it gives one.
    """

    _hidden = ("orbits",)

    def __init__(
        self,
        data: dict,
        orbits: list,
        columns: Sequence[str],
        interrupted: bool = False,
        failure: str | None = None,
    ):
        self._data = data
        self._columns = list(columns)
        #: Each cycle sampled over one period: an (n, 4) array of t/T, s, v, theta.
        self.orbits: list[np.ndarray] = list(orbits)
        #: Whether Ctrl-C stopped the branch.
        self.interrupted = interrupted
        #: The numerical failure that ended a leg, in words (None: none).
        self.failure = failure
        #: The scalar columns of the cycles, one array each.
        self.table: dict[str, np.ndarray] = _table(data["cycles"], self._columns)

    @property
    def kappa_c(self) -> float | None:
        return self._data["kappa_c"]

    @property
    def special_points(self) -> dict[str, np.ndarray]:
        """The bifurcations of cycles on the branch (kind: lpc, pd, ns), a table."""
        return _table(self._data["special_points"], ["kind", *self._columns])

    @property
    def requested_points(self) -> list[dict]:
        return copy.deepcopy(self._data["requested_points"])

    @property
    def operating_point(self) -> dict | None:
        """The cycle at the scene's own stiffness, computed before the branch
        where the scene (or `set`) gives K: `regime` as `hopf` reports it,
        `cycle` (the fields of a cycle; None in steady sliding), `method`
        (`simulation`: a simulated orbit corrected by collocation at K;
        `continuation`: along the branch from the Hopf point, where the first
        failed, `fallback_reason` saying why), `slip_um`, `simulation`.
        None without K."""
        return copy.deepcopy(self._data.get("operating_point"))

    @property
    def lpc_curve(self) -> dict[str, np.ndarray]:
        """The curve of folds of cycles in (kappa, nu) (`lpc_curve=True`), a table."""
        return _table(self._data["lpc_curve"])

    @property
    def multipliers(self) -> list[np.ndarray]:
        """The Floquet multipliers of each cycle, complex, by decreasing modulus."""
        return [
            np.array([complex(re, im) for re, im in c["multipliers"]], dtype=complex)
            for c in self._data["cycles"]
        ]

    def orbit(self, i: int) -> dict[str, np.ndarray]:
        """Cycle `i` over one period: t/T, s (spring force / W), v (slip
        velocity / V0), theta (state / its steady value at V0)."""
        o = self.orbits[i]
        return {"t_over_T": o[:, 0], "s": o[:, 1], "v": o[:, 2], "theta": o[:, 3]}

    def __len__(self) -> int:
        return len(self._data["cycles"])

    def to_pandas(self):
        """The cycles table as a pandas DataFrame, a row per cycle."""
        import pandas as pd

        return pd.DataFrame(self.table)

    def __reduce__(self):
        return (
            _rebuilt,
            (
                Cycles,
                (self._data, self.orbits, self._columns, self.interrupted, self.failure),
                self._request,
            ),
        )

    def __repr__(self) -> str:
        n = len(self)
        span = ""
        control = self._data.get("control")
        if n and control:
            col = {"V": "V_um_per_s", "M": "M_kg", "W": "W_N", "tau": "tau_s"}.get(
                control["param"], control["continued"])
            x = self.table.get(col, self.table.get(control["continued"]))
            if x is not None:
                span = f", {control['param']} {np.nanmin(x):.6e} .. {np.nanmax(x):.6e} {control['unit']}"
        elif n:
            k = self.table["kappa"]
            span = f", kappa {k.min():.6e} .. {k.max():.6e}"
        state = "complete" if self.complete else "partial"
        return f"<Cycles {self._data['scene']}: {n} cycles{span}; {state}: {self.stop}>"


def hopf(
    scene: Scene | str | None = None,
    param: str | None = None,
    from_: float | None = None,
    to: float | None = None,
    *,
    model: str | None = None,
    inertia_threshold: float | None = None,
    from_file: str | os.PathLike | None = None,
    index: int | None = None,
) -> Hopf:
    """The stick-slip onset of `scene` (`stickslip hopf`): where steady
    sliding turns into stick-slip as the stiffness decreases, its frequency,
    next to Appendix C's closed forms, and its type from the normal form
    (first Lyapunov coefficient l1 with a bound on its rounding error).

    scene: a `Scene`, a built-in name or a scene file (default: pmma).
    param: the control parameter of the onset, everything else at the
        scene's values: K [N/m] (the default), V [µm/s], M [kg], W [N],
        tau [s], eta [s/m], or kappa, nu, m, A, B, mu2, theta_c, mu_vv, mu_vphi.
    from_, to: the range searched, in the unit of `param` (not for the
        stiffness; default: the scene's V_range for V and nu, 1e-3 to 1e3
        times the scene's value otherwise).
    model: "inertial" or "quasi-static", forced (default: chosen from the
        inertia ratio m nu^2 / mu_v against `inertia_threshold`, 1e-3).
    from_file, index: the onset at the parameters of the cycle or point
        labelled `index` of a JSON that `stickslip cycles --json` or
        `stickslip branch --json` printed, or of a saved `to_dict()` of
        `branch()` or of `cycles(orbits_file=...)` (as `stickslip hopf
        --from FILE --index N`); the scene and overrides are the file's
        (leave out `scene`, `model` and overrides); `restarted_from` in
        the result names the point.

    Returns a `Hopf` whose `to_dict()` is `stickslip hopf --json`'s output.
    Raises `InputError` for bad input (naming the field) and
    `NumericalError` when the onset cannot be located.
    """
    arg = _scene_arg(scene, from_file, model, inertia_threshold)
    given = dict(param=param, from_=from_, to=to, from_file=from_file, index=index)
    adhesive = _adhesive("hopf", arg, given)
    if adhesive is not None:
        return adhesive
    data, note = _native.hopf(
        arg,
        None if param is None else str(param),
        None if from_ is None else float(from_),
        None if to is None else float(to),
        None if from_file is None else os.fspath(from_file),
        None if index is None else int(index),
    )
    return Hopf(json.loads(data), note)


def _numbers(name: str, values: Any) -> list[float]:
    if values is None:
        return []
    if isinstance(values, (int, float, np.integer, np.floating)) and not isinstance(values, bool):
        return [float(values)]
    try:
        return [float(v) for v in values]
    except (TypeError, ValueError):
        raise InputError(f"{name} = {values!r}: expected a number or a list of numbers", name) from None


def _at(values: Any) -> list[str]:
    """`at` as `--at` items: a dict {name: value or values}, an item
    "NAME=V1,V2", or a list of such items."""
    if values is None:
        return []
    if isinstance(values, str):
        return [values]
    if isinstance(values, Mapping):
        return [
            f"{name}=" + ",".join(repr(v) for v in _numbers(f"at {name}", v))
            for name, v in values.items()
        ]
    return [str(v) for v in values]


def cycles(
    scene: Scene | str | None = None,
    *,
    kappa_fraction: float = 0.5,
    at_kappa: float | Sequence[float] | None = None,
    at: Mapping[str, Any] | str | Sequence[str] | None = None,
    max_steps: int = 500,
    lpc_curve: bool = False,
    from_simulation: bool = False,
    ntst: int = 40,
    ntst_max: int = 12800,
    collocation: str | None = None,
    param: str | None = None,
    to: float | None = None,
    search: tuple[float, float] | None = None,
    model: str | None = None,
    inertia_threshold: float | None = None,
    from_file: str | os.PathLike | None = None,
    index: int | None = None,
    orbits_file: str | os.PathLike | None = None,
) -> Cycles:
    """The stick-slip cycles of `scene` (`stickslip cycles`): the branch of
    periodic orbits born at the Hopf point, continued by collocation toward
    smaller stiffness, with Floquet multipliers (stability), the folds,
    period doublings and torus bifurcations of cycles located on it.

    scene: a `Scene`, a built-in name or a scene file (default: pmma).
    kappa_fraction: stop when the stiffness falls below this fraction of
        kappa_c (without a Hopf point: of the simulated orbit's stiffness); in (0, 1).
    at_kappa: stiffnesses (dimensionless kappa) at which cycles are located
        exactly and reported.
    at: the same in a unit of choice: {"K": 2.68e5} [N/m], {"K_over_W": ...}
        [1/m], {"kappa": ...}, or the command line's "K=2.68e5,2.7e5" items.
    max_steps: most continuation steps per leg; reaching it keeps the
        cycles with `complete = False`.
    lpc_curve: continue every fold of cycles in (kappa, nu) across the
        scene's velocity range (`lpc_curve` of the result).
    from_simulation: start from a simulated stick-slip orbit even where
        there is a Hopf point (automatic where there is none).
    ntst, ntst_max: initial and largest number of mesh intervals.
    collocation: "gauss" or "radau" instead of the model's choice.
    param, to: `param="K"` (or "kappa") with `to` ends the branch at that
        stiffness in its unit, in place of `kappa_fraction`; another
        control parameter (V [µm/s], M [kg], W [N], tau [s], eta [s/m], nu, m, A, B,
        mu2, theta_c, mu_vv, mu_vphi) continues the cycles in it from its Hopf point up to
        `to` in its unit (`stickslip cycles --param V --to 300`); `at` then
        names it ({"V": [100, 200]}); the cycles carry the control's column
        (`V_um_per_s`, ...); no orbit samples and no figures.
    search: (LO, HI), where the Hopf point in `param` is searched (not for
        the stiffness).
    model, inertia_threshold: as for `hopf`.
    from_file, index: restart from the cycle labelled `index` (its `label`)
        of a JSON that `stickslip cycles --json` printed (saved to a file),
        as `stickslip cycles --from FILE --index N`: its orbit read exactly
        from the run's orbits file and continued both ways; the scene is
        the file's (leave out `scene`, `model` and overrides). The file
        may also be a saved `to_dict()` of a run with `orbits_file`.
    orbits_file: a path to write each labelled cycle's orbit to, exactly,
        one line per cycle (as the command line's
        `<run>-cycles-orbits.jsonl`); the result's `orbits_file` then names
        it, so that its saved `to_dict()` (`json.dump`) can be restarted
        from. Without it `orbits_file` is None and the result cannot be
        restarted from (`from_file` refuses it, naming `orbits_file`).

    Returns a `Cycles` whose `to_dict()` is `stickslip cycles --json`'s
    output (without the files). Ctrl-C stops the branch at the next cycle
    and returns what was computed (`complete = False`, `interrupted`).
    Raises `InputError` for bad input (naming the field), `NumericalError`
    (with `.partial`, the cycles computed before) when a numerical method
    fails.
    """
    if isinstance(max_steps, bool) or not isinstance(max_steps, (int, np.integer)) or max_steps < 0:
        raise InputError(f"max_steps = {max_steps!r} is out of range: expected an integer >= 0", "max_steps")
    for name, n in (("ntst", ntst), ("ntst_max", ntst_max)):
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
            raise InputError(f"{name} = {n!r} is out of range: expected an integer >= 4", name)
    arg = _scene_arg(scene, from_file, model, inertia_threshold)
    given = dict(
        at_kappa=at_kappa, at=at, lpc_curve=lpc_curve, from_simulation=from_simulation,
        collocation=collocation, param=param, to=to, search=search, from_file=from_file,
        index=index, orbits_file=orbits_file,
    )
    adhesive = _adhesive(
        "cycles", arg, given, max_steps=int(max_steps), ntst_max=int(ntst_max)
    )
    if adhesive is not None:
        return adhesive
    out = _native.cycles(
        arg,
        float(kappa_fraction),
        bool(from_simulation),
        int(max_steps),
        int(ntst),
        int(ntst_max),
        collocation,
        bool(lpc_curve),
        _numbers("at_kappa", at_kappa),
        _at(at),
        None if param is None else str(param),
        None if to is None else float(to),
        _pair("search", search),
        None if from_file is None else os.fspath(from_file),
        None if index is None else int(index),
        None if orbits_file is None else os.fspath(orbits_file),
    )
    failure = out["failure"]
    result = Cycles(
        json.loads(out["json"]),
        out["orbits"],
        out["columns"],
        out["interrupted"],
        failure[1] if failure else None,
    )
    result._set_request(
        out["figures"], "cycles", scene,
        dict(kappa_fraction=kappa_fraction, at_kappa=at_kappa, at=at, max_steps=max_steps,
             lpc_curve=lpc_curve, from_simulation=from_simulation, ntst=ntst,
             ntst_max=ntst_max, collocation=collocation, param=param, to=to,
             search=search, model=model, inertia_threshold=inertia_threshold,
             from_file=from_file, index=index),
    )
    if failure and failure[0] == "numerical":
        raise NumericalError(failure[1], partial=result)
    return result


def _rebuilt(cls, args, request):
    """A result read back from a pickle (its figures computed again on demand)."""
    r = cls(*args)
    r._request = request
    return r


def _pair(name: str, value: Any) -> tuple[float, float] | None:
    """An optional (LO, HI) pair of numbers."""
    if value is None:
        return None
    try:
        lo, hi = value
        return (float(lo), float(hi))
    except (TypeError, ValueError):
        raise InputError(f"{name} = {value!r}: expected a pair (LO, HI) of numbers", name) from None


def _count(name: str, value: Any, least: int = 0) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < least:
        raise InputError(
            f"{name} = {value!r} is out of range: expected an integer >= {least}", name
        )
    return int(value)


def _failed(out: dict, result: Any) -> Any:
    """`result`, or NumericalError carrying it when a numerical failure ended the job."""
    failure = out["failure"]
    if failure and failure[0] == "numerical":
        raise NumericalError(failure[1], partial=result)
    return result


class Branch(_Columns, _Result):
    """Steady sliding continued in a parameter (`stickslip.branch`): a row
    per point with the state, the three eigenvalues, the bifurcation
    located there (`event`: hopf, fold) and the point in physical units.

    `table` holds every column of the CSV (`branch --csv`) as a numpy array
    (the continued parameter first, named as it is: `kappa`, `nu`, `m`);
    each is also an attribute (`branch.nu`, `branch.eig_re_1`,
    `branch.V_um_per_s`, ...); `eigenvalues` is the (n, 3) complex array;
    `events` the rows of the located bifurcations.
    """

    def __init__(self, data: dict, interrupted: bool = False, failure: str | None = None):
        self._data = data
        #: Whether Ctrl-C stopped the branch.
        self.interrupted = interrupted
        #: The numerical failure that ended the branch, in words (None: none).
        self.failure = failure
        self.table: dict[str, np.ndarray] = _table(data["points"])

    @property
    def param(self) -> str:
        """The dimensionless parameter continued (kappa, nu, m, ...)."""
        return self._data["param"]

    @property
    def eigenvalues(self) -> np.ndarray:
        """The eigenvalues at each point, an (n, 3) complex array (NaN where fewer)."""
        t = self.table
        cols = []
        for i in (1, 2, 3):
            re = np.asarray(t[f"eig_re_{i}"], dtype=float)
            im = np.asarray(t[f"eig_im_{i}"], dtype=float)
            cols.append(re + 1j * im)
        return np.stack(cols, axis=1) if len(self) else np.zeros((0, 3), complex)

    @property
    def events(self) -> dict[str, np.ndarray]:
        """The located bifurcations (rows with an `event`), a table."""
        mask = np.array([p["event"] is not None for p in self._data["points"]], dtype=bool)
        return {k: v[mask] for k, v in self.table.items()}

    def __len__(self) -> int:
        return len(self._data["points"])

    def to_pandas(self):
        """The points as a pandas DataFrame, a row per point."""
        import pandas as pd

        return pd.DataFrame(self.table)

    def __reduce__(self):
        return (Branch, (self._data, self.interrupted, self.failure))

    def __repr__(self) -> str:
        n, p = len(self), self.param
        span = ""
        if n:
            x = self.table[p]
            span = f", {p} {x[0]:.6e} .. {x[-1]:.6e}"
        ev = [p["event"] for p in self._data["points"] if p["event"]]
        state = "complete" if self.complete else f"partial: {self.stop}"
        found = f"; {', '.join(ev)}" if ev else ""
        return f"<Branch {self._data['scene']} in {p}: {n} points{span}{found}; {state}>"


class Diagram(_Columns, _Drawn):
    """The stability diagram of a scene (`stickslip.diagram`): the Hopf
    curve in (velocity, stiffness) with the onset type along it, the Bautin
    points, the curves of folds of cycles bounding the hysteretic region,
    the rig's operating point; with `x`, `y` the Hopf curve in a pair of
    control parameters.

    `hopf_curve`, `special_points`, `lpc_curve` are tables (dicts of numpy
    arrays, the CSV's columns); the Hopf curve's columns are also attributes
    (`d.nu`, `d.kappa`, `d.V_um_per_s`, `d.K_over_W_per_m`, `d.l1`,
    `d.criticality`, ...). `figures(out_dir)` writes the command's figures.
    """

    _table_attr = "hopf_curve"

    def __init__(self, data: dict):
        self._data = data
        key = "hopf_curve" if "hopf_curve" in data else "points"
        self._curve_key = key
        self.hopf_curve: dict[str, np.ndarray] = _table(data.get(key, []))

    @property
    def special_points(self) -> dict[str, np.ndarray]:
        """Bautin points, ends of the curve, ... (kind first), a table."""
        return _table(self._data.get("special_points", []))

    @property
    def lpc_curve(self) -> dict[str, np.ndarray]:
        """The curves of folds of cycles (the hysteresis boundary), a table."""
        return _table(self._data.get("lpc_curve", []))

    @property
    def operating_point(self) -> dict | None:
        """The scene's own stiffness against the diagram (where it gives one)."""
        return copy.deepcopy(self._data.get("operating_point"))

    @property
    def onset_type(self) -> str | None:
        """supercritical, subcritical, degenerate, or mixed along the curve."""
        return self._data.get("onset_type")

    def __len__(self) -> int:
        return len(self._data.get(self._curve_key, []))

    def __eq__(self, other: object) -> bool:
        # The job's time aside.
        if type(self) is not type(other):
            return False
        a, b = dict(self._data), dict(other._data)  # type: ignore[attr-defined]
        a.pop("elapsed_s", None), b.pop("elapsed_s", None)
        return a == b

    __hash__ = None  # type: ignore[assignment]

    def to_pandas(self):
        """The Hopf curve as a pandas DataFrame, a row per point."""
        import pandas as pd

        return pd.DataFrame(self.hopf_curve)

    def __reduce__(self):
        return (_rebuilt, (Diagram, (self._data,), self._request))

    def __repr__(self) -> str:
        state = "complete" if self.complete else f"partial: {self.stop}"
        kinds = self._data.get("special_points", [])
        special = ", ".join(sorted({str(p.get("kind")) for p in kinds}))
        return (
            f"<Diagram {self._data['scene']}: {len(self)} points on the Hopf curve, onset "
            f"{self.onset_type or '-'}{'; ' + special if special else ''}; {state}>"
        )


#: The CSV columns of a simulation (`-simulation.csv`), `model` aside.
SIMULATION_COLUMNS = (
    "t_s", "t", "s", "v", "theta", "slip", "log10_v", "model",
    "spring_force_N", "v_um_per_s", "theta_s", "slip_um",
)


class Simulation(_Drawn):
    """Driven sliding in time (`stickslip.simulate`): every integrator step
    as a row of `-simulation.csv`, its columns numpy arrays and attributes:
    `t_s` [s], `t` [D0/V0], `s` (spring force / W), `v` [V0], `theta`
    [D0/V0], `slip` [D0], `log10_v`, `model` (per step), `spring_force_N`,
    `v_um_per_s`, `theta_s`, `slip_um`. `regime` is the regime reached
    after a complete run: {"kind": "periodic", "period_s", "force_drop_N",
    "slip_um", ...}, {"kind": "steady"}, {"kind": "held"} (the last segment stops the drive:
    the block creeps toward rest) or {"kind": "unsettled", "reason"}.
    `to_dict()` is `stickslip simulate --json` without `files`: the run's
    record (steps, times, the switch, the regime), no time series.
    """

    def __init__(
        self,
        data: dict,
        columns: Mapping[str, np.ndarray],
        interrupted: bool = False,
        failure: str | None = None,
    ):
        self._data = data
        self._columns = {k: np.asarray(v) for k, v in columns.items()}
        self.interrupted = interrupted
        self.failure = failure

    @property
    def table(self) -> dict[str, np.ndarray]:
        """The CSV's columns, in its order."""
        c = self._columns
        out = {}
        for name in SIMULATION_COLUMNS:
            if name == "model":
                out[name] = np.where(c["inertial"], "inertial", "quasi-static")
            else:
                out[name] = c[name]
        return out

    @property
    def regime(self) -> dict | None:
        """The regime reached after a complete run (None: cut short)."""
        return copy.deepcopy(self._data["regime"])

    @property
    def period_s(self) -> float | None:
        r = self._data["regime"]
        return r.get("period_s") if r else None

    @property
    def force_drop_N(self) -> float | None:
        r = self._data["regime"]
        return r.get("force_drop_N") if r else None

    @property
    def slip_um(self) -> np.ndarray:
        return self._columns["slip_um"]

    @property
    def model(self) -> np.ndarray:
        """The model of each step."""
        return np.where(self._columns["inertial"], "inertial", "quasi-static")

    def __len__(self) -> int:
        return len(self._columns["t"])

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        columns = self.__dict__.get("_columns", {})
        if name in columns and name != "inertial":
            return columns[name]
        data = self.__dict__.get("_data", {})
        if name in data:
            return copy.deepcopy(data[name])
        raise AttributeError(f"'Simulation' has no attribute {name!r}")

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(SIMULATION_COLUMNS) | set(self._data))

    def __eq__(self, other: object) -> bool:
        return (
            type(self) is type(other)
            and self._data == other._data  # type: ignore[attr-defined]
            and self._columns.keys() == other._columns.keys()  # type: ignore[attr-defined]
            and all(
                np.array_equal(v, other._columns[k], equal_nan=v.dtype.kind == "f")  # type: ignore[attr-defined]
                for k, v in self._columns.items()
            )
        )

    __hash__ = None  # type: ignore[assignment]

    def to_pandas(self):
        """The time series as a pandas DataFrame, a row per step (the CSV)."""
        import pandas as pd

        return pd.DataFrame(self.table)

    def __reduce__(self):
        return (
            _rebuilt,
            (Simulation, (self._data, self._columns, self.interrupted, self.failure), self._request),
        )

    def __repr__(self) -> str:
        r = self._data["regime"]
        if r and r["kind"] == "periodic":
            what = (f"stick-slip, period {r['period_s']:.6e} s, force drop "
                    f"{r['force_drop_N']:.6e} N, slip {r['slip_um']:.6e} um")
        elif r:
            what = r["kind"]
        else:
            what = f"partial: {self.stop}"
        return (f"<Simulation {self._data['label']}: {len(self)} steps over "
                f"{self._data['t_reached_s']:.6e} s; {what}>")


def branch(
    scene: Scene | str | None = None,
    param: str | None = None,
    from_: float | None = None,
    to: float | None = None,
    max_steps: int = 2000,
    *,
    model: str | None = None,
    inertia_threshold: float | None = None,
    from_file: str | os.PathLike | None = None,
    index: int | None = None,
) -> Branch:
    """Steady sliding continued in a parameter (`stickslip branch`), with
    the eigenvalues at every point and the bifurcations located on it.

    scene: a `Scene`, a built-in name or a scene file (default: pmma).
    param: kappa (the default) or nu, or a control parameter in its unit:
        K [N/m], V [µm/s], M [kg], tau [s], eta [s/m], or m, A, B, mu2, theta_c,
        mu_vv, mu_vphi (the rows are in the dimensionless parameter it moves).
    from_, to: the range, in the unit of `param` (default: kappa, K — from
        a stable stiffness to 1e-3 of it; nu, V — the scene's velocity
        range; others — the scene's value to 1e3 times it).
    max_steps: most continuation steps; a branch short of `to` is returned
        with `complete = False`.
    model, inertia_threshold: as for `hopf`.
    from_file, index: continue from the point labelled `index` of a JSON
        that `stickslip branch --json` printed or a saved `to_dict()` of
        `branch()` (as `stickslip branch --from FILE --index N`): the
        file's scene, overrides and model, from the point's value exactly,
        in the file's parameter (to its `to`, or `to`) or in `param`; leave
        out `scene`, `model`, overrides and `from_`.

    Returns a `Branch` whose `to_dict()` is `stickslip branch --json`'s
    output. Ctrl-C stops the branch and returns its points (`interrupted`).
    Raises `InputError` for bad input, `NumericalError` (with `.partial`)
    when the continuation fails.
    """
    arg = _scene_arg(scene, from_file, model, inertia_threshold)
    # An adhesive scene's steady branch runs in V, over its V_range.
    adhesive_param = None if param in (None, "V") else param
    given = dict(param=adhesive_param, from_=from_, to=to, from_file=from_file, index=index)
    adhesive = _adhesive("branch", arg, given)
    if adhesive is not None:
        return adhesive
    out = _native.branch(
        arg,
        None if param is None else str(param),
        None if from_ is None else float(from_),
        None if to is None else float(to),
        _count("max_steps", max_steps),
        None if from_file is None else os.fspath(from_file),
        None if index is None else int(index),
    )
    failure = out["failure"]
    result = Branch(json.loads(out["json"]), out["interrupted"], failure[1] if failure else None)
    return _failed(out, result)


#: The default step limit along the Hopf curve (the command's --max-steps).
DEFAULT_CURVE_STEPS: int = _native.DEFAULT_CURVE_STEPS


def diagram(
    scene: Scene | str | None = None,
    nu_range: tuple[float, float] | None = None,
    max_steps: int | None = None,
    x: str | None = None,
    y: str | None = None,
    x_range: tuple[float, float] | None = None,
    y_range: tuple[float, float] | None = None,
    *,
    model: str | None = None,
    inertia_threshold: float | None = None,
) -> Diagram:
    """The stability diagram of a scene (`stickslip diagram`): the Hopf
    curve (critical stiffness against the driving velocity) with the onset
    type along it, Bautin points where it changes, the curves of folds of
    cycles bounding the hysteretic region, the rig's operating point.

    scene: a `Scene`, a built-in name or a scene file (default: pmma).
    nu_range: (LO, HI), the velocity range in units of V0 (default: the
        scene's V_range).
    max_steps: most continuation steps along the Hopf curve in each
        direction (default: the command's); a curve cut short by it is
        returned with `complete = False`.
    x, y: the diagram in a pair of control parameters (`--x P --y Q`): x
        varied along the curve (K, V, M, W, tau, kappa, nu, ...; default V),
        y the one whose critical value is traced (default K).
    x_range, y_range: (LO, HI) of x and bounds of y, in their units.
    model, inertia_threshold: as for `hopf`.

    Returns a `Diagram` whose `to_dict()` is `stickslip diagram --json`'s
    output (`files` empty, `elapsed_s` this job's time); `figures(out_dir)`
    writes its figures. The diagram's job has no stop hook: Ctrl-C takes
    effect when it returns.
    """
    s = _scene(scene)
    given = dict(nu_range=nu_range, max_steps=max_steps, x=x, y=y, x_range=x_range, y_range=y_range)
    adhesive = _adhesive("diagram", s._arg(model, inertia_threshold), given)
    if adhesive is not None:
        return adhesive
    out = _native.diagram(
        s._arg(model, inertia_threshold),
        _pair("nu_range", nu_range),
        None if max_steps is None else _count("max_steps", max_steps),
        None if x is None else str(x),
        None if y is None else str(y),
        _pair("x_range", x_range),
        _pair("y_range", y_range),
    )
    result = Diagram(json.loads(out["json"]))
    result._set_request(
        out["figures"], "diagram", s,
        dict(nu_range=nu_range, max_steps=max_steps, x=x, y=y, x_range=x_range,
             y_range=y_range, model=model, inertia_threshold=inertia_threshold),
    )
    return result


def _protocol(protocol: Any) -> list[tuple[float, float]] | None:
    if protocol is None:
        return None
    if isinstance(protocol, str):
        items = [p.split(":") for p in protocol.split(",")]
    else:
        items = list(protocol)
    out = []
    for item in items:
        try:
            v, t = item
            out.append((float(v), float(t)))
        except (TypeError, ValueError):
            raise InputError(
                f"protocol item {item!r}: expected (V [µm/s], duration [s]), "
                "e.g. [(1, 100), (10, 20), (0, 300)]",
                "protocol",
            ) from None
    if not out:
        raise InputError("protocol = []: give at least one (V, duration)", "protocol")
    return out


def simulate(
    scene: Scene | str | None = None,
    protocol: Sequence[tuple[float, float]] | str | None = None,
    *,
    perturb: float = 1e-2,
    rtol: float = 1e-8,
    max_steps: int = 200_000,
    plot_points: int = 20_000,
    model: str | None = None,
    inertia_threshold: float | None = None,
) -> Simulation:
    """Driven sliding in time (`stickslip simulate`) from steady sliding,
    its age perturbed, under a protocol of pulling velocities.

    scene: a `Scene`, a built-in name or a scene file (default: pmma); it
        needs a stiffness (K, or kappa with `with_`).
    protocol: [(V [µm/s], duration [s]), ...]; V = 0 stops the drive (or
        the command line's "1:100,10:20"). Default: the scene's velocity
        for 40 D0/V.
    perturb: relative perturbation of the initial age.
    rtol: the integrator's relative tolerance.
    max_steps: most integrator steps (rows); a run cut short by it is
        returned with `complete = False`.
    plot_points: most points the figures draw (the extremes kept).
    model, inertia_threshold: as for `hopf` (the model is chosen at the
        protocol's fastest velocity; the run switches to the inertial model
        where inertia matters).

    Returns a `Simulation`: every step's row as numpy columns, the regime
    reached, `figures(out_dir)` (spring force and slip velocity against
    time). Ctrl-C stops the run and returns the steps so far.
    """
    s = _scene(scene)
    adhesive = _adhesive(
        "simulate", s._arg(model, inertia_threshold), {},
        protocol=_protocol(protocol), perturb=float(perturb), rtol=float(rtol),
        max_steps=_count("max_steps", max_steps),
    )
    if adhesive is not None:
        return adhesive
    out = _native.simulate(
        s._arg(model, inertia_threshold),
        _protocol(protocol),
        float(perturb),
        float(rtol),
        _count("max_steps", max_steps),
        _count("plot_points", plot_points),
    )
    failure = out["failure"]
    result = Simulation(
        json.loads(out["json"]), out["columns"], out["interrupted"],
        failure[1] if failure else None,
    )
    result._set_request(
        out["figures"], "simulate", s,
        dict(protocol=protocol, perturb=perturb, rtol=rtol, max_steps=max_steps,
             plot_points=plot_points, model=model, inertia_threshold=inertia_threshold),
    )
    return _failed(out, result)


from ._sweep import sweep  # noqa: E402


class Fit(_Drawn):
    """The friction law's parameters fitted to laboratory data
    (`stickslip.fit`): `parameters` ({name: {value, std_error, unit,
    status, start}}), `correlation`, `chi2_per_dof`, `datasets` (RMS
    residuals), `not_determined` (what the data cannot fix and which data
    would), `closed_form` (the seed's route, beside the fit), and
    `fitted_toml` / `scene()`, the fitted scene for every other job.
    `to_dict()` is `stickslip fit --json` without `files`.
    """

    def __init__(self, data: dict, fitted_toml: str):
        self._data = data
        #: The fitted scene as the text of a scene file (`<run>-fitted.toml`).
        self.fitted_toml = fitted_toml

    @property
    def parameters(self) -> dict:
        return copy.deepcopy(self._data["parameters"])

    def value(self, name: str) -> float:
        """The fitted (or kept) value of parameter `name`, in its unit."""
        return self._data["parameters"][name]["value"]

    def std_error(self, name: str) -> float | None:
        """Its standard error (None where it was not fitted)."""
        return self._data["parameters"][name]["std_error"]

    @property
    def correlation(self) -> dict:
        return copy.deepcopy(self._data["correlation"])

    @property
    def chi2_per_dof(self) -> float:
        return self._data["chi2_per_dof"]

    @property
    def not_determined(self) -> list:
        return copy.deepcopy(self._data["not_determined"])

    def scene(self) -> "Scene":
        """The fitted scene."""
        return Scene.from_toml_text(self.fitted_toml)

    def to_pandas(self):
        """A row per parameter: value, std_error, unit, status, start."""
        import pandas as pd

        return pd.DataFrame.from_dict(self._data["parameters"], orient="index")

    def __reduce__(self):
        return (_rebuilt, (Fit, (self._data, self.fitted_toml), self._request))

    def __repr__(self) -> str:
        values = ", ".join(
            f"{n} = {p['value']:.4g}" + (f" ± {p['std_error']:.2g}" if p["std_error"] else "")
            for n, p in self._data["parameters"].items()
        )
        return f"<Fit {self._data['scene']}: {values}>"


def fit(
    scene: Scene | str | None = None,
    data: Sequence[tuple[str, str | os.PathLike]] | Mapping[str, str | os.PathLike] = (),
    free: Sequence[str] | str | None = None,
) -> Fit:
    """The friction law's parameters (mu0, A, B, D0, and mu2 or tau by the
    scene's form) fitted to laboratory data (`stickslip fit`), by joint
    weighted least squares with standard errors and correlations.

    scene: the rig the data were taken on (its V0, M, W, and K for the
        time series) and the start
        of the fit (default: pmma).
    data: (kind, file) pairs, or a dict kind -> file: "steady" (CSV
        columns V_um_s, mu), "onset" (V_um_s, K_over_W_per_m, optionally
        frequency_hz), "velocity_step" (t_s, V_um_s, mu: friction under a
        protocol of load-point velocities, each row's until the next
        row's time) or "relaxation" (t_s, slip_um, V_um_s: the slip after
        the drive stops at t = 0, one velocity per file); the time series
        are integrated on the scene's rig (its K, W, M). An optional sigma
        column (sigma_frequency_hz for the frequency) gives each row's
        error, else it is estimated.
    free: the parameters to fit (default: all of the law's).

    An adhesive scene (law = "adhesive", e.g. "gel") is fitted with its own
    law (F_a, V_s, tau_on, tau_out, F_v, alpha) to "steady" (V_um_s, F_N:
    the friction force) and "onset" (V_um_s, K_N_per_m: the critical
    stiffness) data; see docs/fit.md, "Adhesive scenes".

    Returns a `Fit`; `complete` is False (not an exception) when the data
    leave a parameter undetermined: it is named in `not_determined` with
    the data that would determine it, and kept at the scene's value.
    Raises `InputError` for bad data (naming file, row and column).
    """
    s = _scene(scene)
    items = list(data.items()) if isinstance(data, Mapping) else list(data)
    pairs = []
    for item in items:
        try:
            kind, path = item
        except (TypeError, ValueError):
            raise InputError(f"data item {item!r}: expected (kind, file)", "data") from None
        pairs.append((str(kind), os.fspath(path)))
    if isinstance(free, str):
        free = [f.strip() for f in free.split(",")]
    out = _native.fit(s._arg(None, None), pairs, None if free is None else [str(f) for f in free])
    result = Fit(json.loads(out["json"]), out["fitted_toml"])
    result._set_request(out["figures"], "fit", s, dict(data=pairs, free=free))
    return result
