"""Type stubs of stickslip (python/stickslip/__init__.py)."""

import os
from typing import Any, Literal, Mapping, Sequence

import numpy as np
import numpy.typing as npt

from ._errors import InputError as InputError
from ._errors import NumericalError as NumericalError

DEFAULT_INERTIA_THRESHOLD: float
DEFAULT_SCENE: str

Model = Literal["inertial", "quasi-static"]

def scenes() -> dict[str, str]: ...

StateLaw = Literal["ageing", "slip"]

class Scene:
    # The scene file's keys (docs/model.md): the friction law's A, B, mu0,
    # mu2, mu_vv, mu_vphi (dimensionless), tau [s], eta [s/m] (radiation
    # damping), state_law; D0 [µm],
    # V0 [µm/s], M [kg], W [N], g [m/s^2], K [N/m], V [µm/s], V_range [µm/s].
    def __init__(
        self,
        *,
        name: str = ...,
        description: str = ...,
        A: float,
        B: float = ...,
        mu0: float = ...,
        mu2: float = ...,
        mu_vv: float = ...,
        mu_vphi: float = ...,
        tau: float = ...,
        eta: float = ...,
        state_law: StateLaw = ...,
        D0: float = ...,
        V0: float = ...,
        M: float = ...,
        W: float = ...,
        g: float = ...,
        K: float = ...,
        V: float = ...,
        V_range: Sequence[float] = ...,
    ) -> None: ...
    @classmethod
    def builtin(cls, name: str = ...) -> Scene: ...
    @classmethod
    def from_toml(cls, path: str | os.PathLike[str]) -> Scene: ...
    @classmethod
    def from_toml_text(cls, text: str, name: str = ...) -> Scene: ...
    # The names `--set` takes: the dimensionless parameters, or the scene
    # keys in their units (V_range a pair), or the state law.
    def with_(
        self,
        *,
        kappa: float = ...,
        nu: float = ...,
        m: float = ...,
        A: float = ...,
        B: float = ...,
        mu0: float = ...,
        mu2: float = ...,
        theta_c: float = ...,
        mu_vv: float = ...,
        mu_vphi: float = ...,
        eta_d: float = ...,
        K: float = ...,
        M: float = ...,
        W: float = ...,
        V: float = ...,
        V0: float = ...,
        D0: float = ...,
        tau: float = ...,
        g: float = ...,
        eta: float = ...,
        V_range: tuple[float, float] = ...,
        state_law: StateLaw = ...,
    ) -> Scene: ...
    def to_toml(self) -> str: ...
    @property
    def name(self) -> str: ...
    @property
    def description(self) -> str: ...
    @property
    def label(self) -> str: ...
    @property
    def overrides(self) -> tuple[str, ...]: ...
    @property
    def params(self) -> dict[str, float]: ...
    @property
    def units(self) -> dict[str, Any]: ...
    @property
    def model(self) -> str: ...
    def __eq__(self, other: object) -> bool: ...
    def __hash__(self) -> int: ...

class Adhesive:
    """A job's result on an adhesive scene (law = "adhesive"): the command's JSON."""
    def to_dict(self) -> dict: ...
    def to_json(self, indent: int | None = 2) -> str: ...
    def __getitem__(self, key: str) -> Any: ...
    @property
    def complete(self) -> bool: ...
    @property
    def stop(self) -> str | None: ...

class Hopf:
    note: str | None
    def to_dict(self) -> dict[str, Any]: ...
    def to_json(self, indent: int | None = ...) -> str: ...
    def to_pandas(self) -> Any: ...
    def __getitem__(self, key: str) -> Any: ...
    @property
    def complete(self) -> bool: ...
    @property
    def stop(self) -> str: ...
    @property
    def status(self) -> Literal["hopf", "stable_for_all_stiffness"]: ...
    @property
    def found(self) -> bool: ...
    @property
    def kappa_c(self) -> float | None: ...
    @property
    def omega_c(self) -> float | None: ...
    @property
    def K_c(self) -> float | None: ...
    @property
    def l1(self) -> float | None: ...
    @property
    def l1_error_bound(self) -> float | None: ...
    @property
    def criticality(self) -> Literal["supercritical", "subcritical", "degenerate"] | None: ...
    @property
    def appendix_c(self) -> dict[str, Any] | None: ...
    @property
    def model(self) -> str: ...
    @property
    def params(self) -> dict[str, float]: ...
    @property
    def operating_point(self) -> dict[str, Any] | None: ...
    @property
    def critical(self) -> dict[str, Any] | None: ...

class Cycles:
    orbits: list[npt.NDArray[np.float64]]
    interrupted: bool
    failure: str | None
    table: dict[str, np.ndarray]
    # The scalar columns of the cycles table, one entry per cycle.
    kappa: npt.NDArray[np.float64]
    period: npt.NDArray[np.float64]
    delta_s: npt.NDArray[np.float64]
    s_min: npt.NDArray[np.float64]
    s_max: npt.NDArray[np.float64]
    v_min: npt.NDArray[np.float64]
    v_max: npt.NDArray[np.float64]
    stable: np.ndarray
    trivial_multiplier_error: npt.NDArray[np.float64]
    error_estimate: npt.NDArray[np.float64]
    ntst: npt.NDArray[np.int64]
    user_point: npt.NDArray[np.bool_]
    model: np.ndarray
    inertial_imbalance: npt.NDArray[np.float64]
    K_over_W_per_m: npt.NDArray[np.float64]
    period_s: npt.NDArray[np.float64]
    v_min_um_per_s: npt.NDArray[np.float64]
    v_max_um_per_s: npt.NDArray[np.float64]
    m: npt.NDArray[np.float64]
    friction_min: npt.NDArray[np.float64]
    K_N_per_m: npt.NDArray[np.float64]
    delta_s_N: npt.NDArray[np.float64]
    def to_dict(self) -> dict[str, Any]: ...
    def to_json(self, indent: int | None = ...) -> str: ...
    def to_pandas(self) -> Any: ...
    def __getitem__(self, key: str) -> Any: ...
    def __len__(self) -> int: ...
    def __getattr__(self, name: str) -> Any: ...
    @property
    def complete(self) -> bool: ...
    @property
    def stop(self) -> str: ...
    @property
    def kappa_c(self) -> float | None: ...
    @property
    def special_points(self) -> dict[str, np.ndarray]: ...
    @property
    def requested_points(self) -> list[dict[str, Any]]: ...
    @property
    def lpc_curve(self) -> dict[str, np.ndarray]: ...
    @property
    def multipliers(self) -> list[npt.NDArray[np.complex128]]: ...
    def orbit(self, i: int) -> dict[str, npt.NDArray[np.float64]]: ...
    def figures(self, out_dir: str | os.PathLike[str] = ...) -> list[str]: ...

class Branch:
    interrupted: bool
    failure: str | None
    table: dict[str, np.ndarray]
    def to_dict(self) -> dict[str, Any]: ...
    def to_json(self, indent: int | None = ...) -> str: ...
    def to_pandas(self) -> Any: ...
    def __getitem__(self, key: str) -> Any: ...
    def __len__(self) -> int: ...
    def __getattr__(self, name: str) -> np.ndarray: ...
    @property
    def complete(self) -> bool: ...
    @property
    def stop(self) -> str | None: ...
    @property
    def param(self) -> str: ...
    @property
    def eigenvalues(self) -> npt.NDArray[np.complex128]: ...
    @property
    def events(self) -> dict[str, np.ndarray]: ...

class Diagram:
    hopf_curve: dict[str, np.ndarray]
    def to_dict(self) -> dict[str, Any]: ...
    def to_json(self, indent: int | None = ...) -> str: ...
    def to_pandas(self) -> Any: ...
    def __getitem__(self, key: str) -> Any: ...
    def __len__(self) -> int: ...
    def __getattr__(self, name: str) -> np.ndarray: ...
    def figures(self, out_dir: str | os.PathLike[str] = ...) -> list[str]: ...
    @property
    def complete(self) -> bool: ...
    @property
    def stop(self) -> str: ...
    @property
    def special_points(self) -> dict[str, np.ndarray]: ...
    @property
    def lpc_curve(self) -> dict[str, np.ndarray]: ...
    @property
    def operating_point(self) -> dict[str, Any] | None: ...
    @property
    def onset_type(self) -> str | None: ...

SIMULATION_COLUMNS: tuple[str, ...]

class Simulation:
    interrupted: bool
    failure: str | None
    t_s: npt.NDArray[np.float64]
    t: npt.NDArray[np.float64]
    s: npt.NDArray[np.float64]
    v: npt.NDArray[np.float64]
    theta: npt.NDArray[np.float64]
    slip: npt.NDArray[np.float64]
    log10_v: npt.NDArray[np.float64]
    spring_force_N: npt.NDArray[np.float64]
    v_um_per_s: npt.NDArray[np.float64]
    theta_s: npt.NDArray[np.float64]
    def to_dict(self) -> dict[str, Any]: ...
    def to_json(self, indent: int | None = ...) -> str: ...
    def to_pandas(self) -> Any: ...
    def __getitem__(self, key: str) -> Any: ...
    def __len__(self) -> int: ...
    def figures(self, out_dir: str | os.PathLike[str] = ...) -> list[str]: ...
    @property
    def table(self) -> dict[str, np.ndarray]: ...
    @property
    def complete(self) -> bool: ...
    @property
    def stop(self) -> str | None: ...
    @property
    def regime(self) -> dict[str, Any] | None: ...
    @property
    def period_s(self) -> float | None: ...
    @property
    def force_drop_N(self) -> float | None: ...
    @property
    def slip_um(self) -> npt.NDArray[np.float64]: ...
    @property
    def model(self) -> npt.NDArray[np.str_]: ...

class Fit:
    fitted_toml: str
    def to_dict(self) -> dict[str, Any]: ...
    def to_json(self, indent: int | None = ...) -> str: ...
    def to_pandas(self) -> Any: ...
    def __getitem__(self, key: str) -> Any: ...
    def figures(self, out_dir: str | os.PathLike[str] = ...) -> list[str]: ...
    def value(self, name: str) -> float: ...
    def std_error(self, name: str) -> float | None: ...
    def scene(self) -> Scene: ...
    @property
    def complete(self) -> bool: ...
    @property
    def stop(self) -> str | None: ...
    @property
    def parameters(self) -> dict[str, dict[str, Any]]: ...
    @property
    def correlation(self) -> dict[str, Any]: ...
    @property
    def chi2_per_dof(self) -> float: ...
    @property
    def not_determined(self) -> list[dict[str, Any]]: ...

def hopf(
    scene: Scene | str | os.PathLike[str] | None = ...,
    param: str | None = ...,
    from_: float | None = ...,
    to: float | None = ...,
    *,
    model: Model | None = ...,
    inertia_threshold: float | None = ...,
    from_file: str | os.PathLike[str] | None = ...,
    index: int | None = ...,
) -> Hopf | Adhesive: ...
def cycles(
    scene: Scene | str | os.PathLike[str] | None = ...,
    *,
    kappa_fraction: float = ...,
    at_kappa: float | Sequence[float] | None = ...,
    at: Mapping[str, float | Sequence[float]] | str | Sequence[str] | None = ...,
    max_steps: int = ...,
    lpc_curve: bool = ...,
    from_simulation: bool = ...,
    ntst: int = ...,
    ntst_max: int = ...,
    collocation: Literal["gauss", "radau"] | None = ...,
    param: str | None = ...,
    to: float | None = ...,
    search: tuple[float, float] | None = ...,
    model: Model | None = ...,
    inertia_threshold: float | None = ...,
    from_file: str | os.PathLike[str] | None = ...,
    index: int | None = ...,
    orbits_file: str | os.PathLike[str] | None = ...,
) -> Cycles | Adhesive: ...

DEFAULT_CURVE_STEPS: int

def branch(
    scene: Scene | str | os.PathLike[str] | None = ...,
    param: str | None = ...,
    from_: float | None = ...,
    to: float | None = ...,
    max_steps: int = ...,
    *,
    model: Model | None = ...,
    inertia_threshold: float | None = ...,
    from_file: str | os.PathLike[str] | None = ...,
    index: int | None = ...,
) -> Branch | Adhesive: ...
def diagram(
    scene: Scene | str | os.PathLike[str] | None = ...,
    nu_range: tuple[float, float] | None = ...,
    max_steps: int | None = ...,
    x: str | None = ...,
    y: str | None = ...,
    x_range: tuple[float, float] | None = ...,
    y_range: tuple[float, float] | None = ...,
    *,
    model: Model | None = ...,
    inertia_threshold: float | None = ...,
) -> Diagram | Adhesive: ...
def simulate(
    scene: Scene | str | os.PathLike[str] | None = ...,
    protocol: Sequence[tuple[float, float]] | str | None = ...,
    *,
    perturb: float = ...,
    rtol: float = ...,
    max_steps: int = ...,
    plot_points: int = ...,
    model: Model | None = ...,
    inertia_threshold: float | None = ...,
) -> Simulation | Adhesive: ...
def sweep(
    job: Literal["hopf", "diagram", "cycles"],
    grid: Mapping[str, Any] | Sequence[Mapping[str, Any]] | Sequence[Scene],
    scene: Scene | str | os.PathLike[str] | None = ...,
    client: Any = ...,
    chunk: int | None = ...,
    out: str | os.PathLike[str] | None = ...,
    *,
    workers: int | None = ...,
    **options: Any,
) -> Any: ...
def fit(
    scene: Scene | str | os.PathLike[str] | None = ...,
    data: Sequence[tuple[str, str | os.PathLike[str]]] | Mapping[str, str | os.PathLike[str]] = ...,
    free: Sequence[str] | str | None = ...,
) -> Fit: ...
