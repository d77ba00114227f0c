"""stickslip from Python: the stick-slip onset of a block pulled through a
spring across a rate-and-state frictional interface, its type, and the
stick-slip cycles, each job one call returning a result object.

    >>> import stickslip
    >>> scene = stickslip.Scene.builtin("pmma").with_(K=2e5)
    >>> h = stickslip.hopf(scene)
    >>> h.kappa_c, h.criticality
    >>> c = stickslip.cycles(scene, kappa_fraction=0.9)
    >>> c.kappa, c.delta_s          # numpy arrays, one entry per cycle

Every result has `.to_dict()` (exactly what `stickslip <command> --json`
prints for the same request), `.complete`, `.stop`, `.to_pandas()` (with
pandas installed), and pickles. Bad input raises `InputError` (a
`ValueError`) naming the field; a numerical failure raises `NumericalError`
with the result computed before it as `.partial`. The GIL is released while
a job computes; Ctrl-C stops a branch of cycles and returns the cycles
computed so far with `complete = False`.

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
    "cycles",
    "Hopf",
    "Cycles",
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
    description, A, B, mu0, mu2, tau [s], D0 [um], V0 [um/s], M [kg], W [N],
    g [m/s^2], K [N/m], V [um/s], V_range [um/s, a pair]); change it with
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

    def _init(self, builtin, toml, origin, stem, overrides) -> None:
        self._builtin: str | None = builtin
        self._toml: str | None = toml
        self._origin: str = origin
        self._stem: str = stem
        self._set: tuple[str, ...] = tuple(overrides)
        self._info = _native.setup(self._arg())

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

    def with_(self, **overrides: Any) -> "Scene":
        """This scene with overrides, named as `--set` takes them: the scene
        keys in their units (K [N/m], M [kg], W [N], V [um/s], tau [s], D0
        [um], V0 [um/s], g [m/s^2], V_range=(LO, HI) [um/s]) or the
        dimensionless parameters (kappa, nu, m, A, B, mu0, mu2, theta_c).
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
    def params(self) -> dict[str, float]:
        """The dimensionless parameters (docs/model.md), overrides applied."""
        return dict(self._info["params"])

    @property
    def units(self) -> dict[str, Any]:
        """The scales: D0 [um], V0 [um/s], M [kg], W [N], V_range [um/s]."""
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

    def __eq__(self, other: object) -> bool:
        return type(self) is type(other) and self._data == other._data  # type: ignore[attr-defined]

    __hash__ = None  # type: ignore[assignment]


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
    def complete(self) -> bool:
        """Always True: the onset job has no partial result (a failure raises)."""
        return True

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


class Cycles(_Result):
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
    `requested_points` and `lpc_curve` are tables of their own.
    """

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
    def complete(self) -> bool:
        """Everything requested was delivered."""
        return self._data["complete"]

    @property
    def stop(self) -> str:
        """How the branch ended, in words."""
        return self._data["stop"]

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

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_") or name in ("table",):
            raise AttributeError(name)
        table = self.__dict__.get("table", {})
        if name in table:
            return table[name]
        data = self.__dict__.get("_data", {})
        if name in data:
            return copy.deepcopy(data[name])
        raise AttributeError(f"'Cycles' has no attribute {name!r}")

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(self.table) | set(self._data))

    def to_pandas(self):
        """The cycles table as a pandas DataFrame, a row per cycle."""
        import pandas as pd

        return pd.DataFrame(self.table)

    def __reduce__(self):
        return (
            Cycles,
            (self._data, self.orbits, self._columns, self.interrupted, self.failure),
        )

    def __repr__(self) -> str:
        n = len(self)
        span = ""
        if n:
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
) -> Hopf:
    """The stick-slip onset of `scene` (`stickslip hopf`): where steady
    sliding turns into stick-slip as the stiffness decreases, its frequency,
    next to Appendix C's closed forms, and its type from the normal form
    (first Lyapunov coefficient l1 with a bound on its rounding error).

    scene: a `Scene`, a built-in name or a scene file (default: pmma).
    param: the control parameter of the onset, everything else at the
        scene's values: K [N/m] (the default), V [um/s], M [kg], W [N],
        tau [s], or kappa, nu, m, A, B, mu2, theta_c.
    from_, to: the range searched, in the unit of `param` (not for the
        stiffness; default: the scene's V_range for V and nu, 1e-3 to 1e3
        times the scene's value otherwise).
    model: "inertial" or "quasi-static", forced (default: chosen from the
        inertia ratio m nu^2 / mu_v against `inertia_threshold`, 1e-3).

    Returns a `Hopf` whose `to_dict()` is `stickslip hopf --json`'s output.
    Raises `InputError` for bad input (naming the field) and
    `NumericalError` when the onset cannot be located.
    """
    s = _scene(scene)
    data, note = _native.hopf(
        s._arg(model, inertia_threshold),
        None if param is None else str(param),
        None if from_ is None else float(from_),
        None if to is None else float(to),
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
    model: str | None = None,
    inertia_threshold: float | None = None,
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
        stiffness in its unit, in place of `kappa_fraction` (other control
        parameters: the command line, for now).
    model, inertia_threshold: as for `hopf`.

    Returns a `Cycles` whose `to_dict()` is `stickslip cycles --json`'s
    output (without the files). Ctrl-C stops the branch at the next cycle
    and returns what was computed (`complete = False`, `interrupted`).
    Raises `InputError` for bad input (naming the field), `NumericalError`
    (with `.partial`, the cycles computed before) when a numerical method
    fails.
    """
    s = _scene(scene)
    if isinstance(max_steps, bool) or not isinstance(max_steps, (int, np.integer)) or max_steps < 0:
        raise InputError(f"max_steps = {max_steps!r} is out of range: expected an integer >= 0", "max_steps")
    for name, n in (("ntst", ntst), ("ntst_max", ntst_max)):
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
            raise InputError(f"{name} = {n!r} is out of range: expected an integer >= 4", name)
    out = _native.cycles(
        s._arg(model, inertia_threshold),
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
    )
    failure = out["failure"]
    result = Cycles(
        json.loads(out["json"]),
        out["orbits"],
        out["columns"],
        out["interrupted"],
        failure[1] if failure else None,
    )
    if failure and failure[0] == "numerical":
        raise NumericalError(failure[1], partial=result)
    return result
