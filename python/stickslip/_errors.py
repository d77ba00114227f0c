"""The exceptions of stickslip: bad input and numerical failure."""

from __future__ import annotations

import re
from typing import Any

# The command line's option names and the keyword names of the functions.
_KEYWORDS = {
    "--kappa-fraction": "kappa_fraction",
    "--from-simulation": "from_simulation",
    "--max-steps": "max_steps",
    "--ntst-max": "ntst_max",
    "--ntst": "ntst",
    "--collocation": "collocation",
    "--lpc-curve": "lpc_curve",
    "--at-kappa": "at_kappa",
    "--at": "at",
    "--param": "param",
    "--from": "from_",
    "--to": "to",
    "--set": "with_",
    "--model": "model",
    "--inertia-threshold": "inertia_threshold",
    "--search": "search",
    "--nu-range": "nu_range",
    "--x-range": "x_range",
    "--y-range": "y_range",
    "--x": "x",
    "--y": "y",
    "--protocol": "protocol",
    "--perturb": "perturb",
    "--rtol": "rtol",
    "--plot-points": "plot_points",
}

_OPTION = re.compile(r"--[a-z][a-z-]*")


def keyword(text: str) -> str:
    """`text` with the command line's option names replaced by the keyword
    names of the Python functions (`--kappa-fraction` -> `kappa_fraction`)."""
    return _OPTION.sub(lambda m: _KEYWORDS.get(m.group(0), m.group(0)), text)


def _field(field: str | None) -> str | None:
    """The field's name for Python: `--set K` is the override `K`,
    `--kappa-fraction` the keyword `kappa_fraction`."""
    if field is None:
        return None
    # A field of a scene file comes after the file's name: `pmma.toml: D0`.
    field = field.rsplit(": ", 1)[-1]
    if field.startswith("--set "):
        return field[len("--set "):]
    return keyword(field)


class InputError(ValueError):
    """Input stickslip refuses: the message names the field, the value and
    what is allowed; `field` is the field's name (a keyword of the function,
    a scene key, an override name), or None for a conflict between fields."""

    def __init__(self, message: str, field: str | None = None):
        message = keyword(message)
        super().__init__(message)
        self.message = message
        self.field = _field(field)

    def __reduce__(self):
        return (_input_error, (self.message, self.field))


def _input_error(message: str, field: str | None) -> InputError:
    e = InputError.__new__(InputError)
    ValueError.__init__(e, message)
    e.message, e.field = message, field
    return e


class NumericalError(RuntimeError):
    """A numerical method that did not deliver, with what was reached and
    what to try. `partial` is the result computed before the failure (a
    result object with `complete = False`), or None when there is none."""

    def __init__(self, message: str, partial: Any = None):
        super().__init__(message)
        self.message = message
        self.partial = partial

    def __reduce__(self):
        return (NumericalError, (self.message, self.partial))
