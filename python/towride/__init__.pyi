import os
from typing import Any, Dict, Iterable, List, Mapping, Optional, Union

import numpy as np
import numpy.typing as npt

from ._errors import InputError as InputError
from ._errors import SolverError as SolverError
from ._errors import TowrideError as TowrideError

__version__: str

PathLike = Union[str, os.PathLike[str]]
Set = Union[Mapping[str, Any], Iterable[str], None]

class Result:
    time: npt.NDArray[np.float64]
    channels: Dict[str, npt.NDArray[np.float64]]
    units: Dict[str, str]
    summary: Dict[str, Any]
    def __init__(self, raw: Dict[str, Any]) -> None: ...
    @property
    def status(self) -> str: ...
    def __getitem__(self, name: str) -> npt.NDArray[np.float64]: ...
    def to_pandas(self) -> Any: ...

class SweepResult(Dict[str, Any]):
    @property
    def rows(self) -> List[Dict[str, Any]]: ...
    def to_pandas(self) -> Any: ...

def run(
    path: PathLike,
    set: Set = ...,
    overrides: Optional[PathLike] = ...,
    out: Optional[PathLike] = ...,
) -> Result: ...
def sweep(
    path: PathLike,
    set: Set = ...,
    overrides: Optional[PathLike] = ...,
    out: Optional[PathLike] = ...,
    jobs: Optional[int] = ...,
) -> SweepResult: ...
def validate(
    path: PathLike,
    set: Set = ...,
    overrides: Optional[PathLike] = ...,
    out: Optional[PathLike] = ...,
    correct: bool = ...,
    max_shift_ms: float = ...,
) -> Dict[str, Any]: ...
def sensitivity(
    path: PathLike,
    set: Set = ...,
    overrides: Optional[PathLike] = ...,
    out: Optional[PathLike] = ...,
    params: Iterable[str] = ...,
    groups: Iterable[str] = ...,
    outputs: Iterable[str] = ...,
    method: str = ...,
    trajectories: int = ...,
    range: Optional[float] = ...,
    seed: int = ...,
    jobs: Optional[int] = ...,
) -> Dict[str, Any]: ...
