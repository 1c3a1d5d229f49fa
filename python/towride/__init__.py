"""towride from Python: run scenes, sweeps, validations and sensitivity studies.

Each function does what the CLI command of the same name does and returns the same data
the command writes, as Python objects (the summaries are the CLI's JSON, parsed; the
channels NumPy arrays). Runs release the GIL: a ``ThreadPoolExecutor`` runs cases in
parallel. Errors raise :class:`InputError` (file, line, field) or :class:`SolverError`
(time reached and the partial result). See docs/python.md.
"""

import json
import os
from typing import Any, Dict, Iterable, List, Mapping, Optional, Union

import numpy as np

from . import _errors
from ._errors import InputError, SolverError, TowrideError
from . import _towride

__version__ = _towride.__version__

__all__ = [
    "InputError",
    "Result",
    "SolverError",
    "SweepResult",
    "TowrideError",
    "run",
    "sensitivity",
    "sweep",
    "validate",
]

PathLike = Union[str, "os.PathLike[str]"]
Set = Union[Mapping[str, Any], Iterable[str], None]


def _value_text(v: Any) -> str:
    """A Python value as the text of a ``--set`` VALUE (TOML: true, 2.5e4, [1, 0, 0])."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value_text(x) for x in v) + "]"
    if isinstance(v, (int, float, np.integer, np.floating)):
        return repr(float(v)) if isinstance(v, (float, np.floating)) else str(int(v))
    return str(v)


def _set_args(set: Set) -> List[str]:
    """``{"FILE:PATH": value}`` or ``["FILE:PATH=VALUE", ...]`` as the CLI's ``--set``."""
    if set is None:
        return []
    if isinstance(set, str):
        return [set]
    if isinstance(set, Mapping):
        return [f"{k}={_value_text(v)}" for k, v in set.items()]
    return [str(s) for s in set]


def _path(p: Optional[PathLike]) -> Optional[str]:
    return None if p is None else os.fspath(p)


class Result:
    """One run: sample times, channels (NumPy arrays by name), their units and the
    summary (``summary.json`` as a dict).

    Attributes:
        time: sample times [s], shape (n,).
        channels: channel name -> samples, each shape (n,), in SI units.
        units: channel name -> unit (``"N"``, ``"m/s^2"``).
        summary: the run's summary, as the CLI writes ``summary.json``.
    """

    def __init__(self, raw: Dict[str, Any]) -> None:
        self.time: np.ndarray = raw["time"]
        self.channels: Dict[str, np.ndarray] = raw["channels"]
        self.units: Dict[str, str] = raw["units"]
        self.summary: Dict[str, Any] = json.loads(raw["summary_json"])

    @property
    def status(self) -> str:
        """``"completed"``, ``"failed"`` or ``"interrupted"``."""
        return self.summary["status"]

    def __getitem__(self, name: str) -> np.ndarray:
        return self.channels[name]

    def __repr__(self) -> str:
        return (
            f"<towride.Result {self.summary.get('name', '')!r}: {self.status}, "
            f"{len(self.time)} samples, {len(self.channels)} channels>"
        )

    def to_pandas(self) -> Any:
        """The channels as a DataFrame indexed by time, columns ``name [unit]`` as in
        outputs.csv. Needs pandas."""
        import pandas as pd

        cols = {f"{n} [{self.units[n]}]": v for n, v in self.channels.items()}
        return pd.DataFrame(cols, index=pd.Index(self.time, name="time [s]"))


class SweepResult(dict):
    """A sweep as ``towride sweep --json`` prints it (a dict: ``rows``, ``failed``,
    ``wall_s``, ...)."""

    @property
    def rows(self) -> List[Dict[str, Any]]:
        """One dict per case: index, values, status, error, wall_s, figures."""
        return self["rows"]

    def to_pandas(self) -> Any:
        """One row per case: index, status, wall time, the parameters' values
        (``value_0``...) and every figure by its summary.csv header. Needs pandas."""
        import pandas as pd

        table = []
        for r in self.rows:
            row: Dict[str, Any] = {"case": r["index"], "status": r["status"], "wall_s": r["wall_s"]}
            for i, v in enumerate(r["values"]):
                row[f"value_{i}"] = v
            for name, v in r["figures"]:
                row[name] = v
            table.append(row)
        return pd.DataFrame(table)


def run(
    path: PathLike,
    set: Set = None,
    overrides: Optional[PathLike] = None,
    out: Optional[PathLike] = None,
) -> Result:
    """Runs a scene or mechanism file, as ``towride run PATH``.

    Args:
        path: the scene (``[scene]``) or mechanism file (TOML).
        set: values replaced as the files are read, ``{"FILE:PATH": value}`` or
            ``["FILE:PATH=VALUE"]`` (the CLI's ``--set``; FILE matched by the end of
            its path).
        overrides: a run's ``overrides.toml`` (the CLI's ``--overrides``).
        out: a folder for outputs.csv, summary.json, report.html and plots.png (as the
            CLI writes them); nothing is written when None.

    Raises:
        InputError: a bad file or value (``file``, ``line``, ``field``).
        SolverError: the solver stopped the run (``time``, partial ``result``).
    """
    raw = _towride.run(os.fspath(path), _set_args(set), _path(overrides), _path(out))
    res = Result(raw)
    if raw["failure"] is not None:
        message, t = raw["failure"]
        raise SolverError(message, t, res)
    return res


def sweep(
    path: PathLike,
    set: Set = None,
    overrides: Optional[PathLike] = None,
    out: Optional[PathLike] = None,
    jobs: Optional[int] = None,
) -> SweepResult:
    """Runs a sweep file's cases on ``jobs`` threads (default: all cores), as
    ``towride sweep PATH --json``; with ``out``, also writes summary.csv, summary.json
    and report.html there. A failed case is a row with status ``failed``."""
    text = _towride.sweep(os.fspath(path), _set_args(set), _path(overrides), _path(out), jobs)
    return SweepResult(json.loads(text))


def validate(
    path: PathLike,
    set: Set = None,
    overrides: Optional[PathLike] = None,
    out: Optional[PathLike] = None,
    correct: bool = True,
    max_shift_ms: float = 100.0,
) -> Dict[str, Any]:
    """Compares recorded runs (a RUN.toml or a folder of them) with the simulation, as
    ``towride validate PATH --json --no-plots``; with ``out``, writes summary.csv and
    summary.json there. ``correct=False`` is ``--no-correct``."""
    text = _towride.validate(
        os.fspath(path), _set_args(set), _path(overrides), _path(out), correct, max_shift_ms
    )
    return json.loads(text)


def sensitivity(
    path: PathLike,
    set: Set = None,
    overrides: Optional[PathLike] = None,
    out: Optional[PathLike] = None,
    params: Iterable[str] = (),
    groups: Iterable[str] = (),
    outputs: Iterable[str] = (),
    method: str = "oat",
    trajectories: int = 10,
    range: Optional[float] = None,
    seed: int = 1,
    jobs: Optional[int] = None,
) -> Dict[str, Any]:
    """OAT elasticities or Morris screening of a scene's outputs, as ``towride
    sensitivity PATH --json``; with ``out``, writes sensitivity.csv/.json/.html and
    tornado.png there."""
    text = _towride.sensitivity(
        os.fspath(path),
        _set_args(set),
        _path(overrides),
        _path(out),
        list(params),
        list(groups),
        list(outputs),
        method,
        trajectories,
        range,
        seed,
        jobs,
    )
    return json.loads(text)


del _errors
