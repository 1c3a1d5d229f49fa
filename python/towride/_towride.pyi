# Stubs of the extension module (python/src/lib.rs); the public API is in __init__.pyi.
from typing import Any, Dict, List, Optional

__version__: str

def run(path: str, set: List[str] = ..., overrides: Optional[str] = ..., out: Optional[str] = ...) -> Dict[str, Any]: ...
def sweep(path: str, set: List[str] = ..., overrides: Optional[str] = ..., out: Optional[str] = ..., jobs: Optional[int] = ...) -> str: ...
def validate(path: str, set: List[str] = ..., overrides: Optional[str] = ..., out: Optional[str] = ..., correct: bool = ..., max_shift_ms: float = ...) -> str: ...
def sensitivity(
    path: str,
    set: List[str] = ...,
    overrides: Optional[str] = ...,
    out: Optional[str] = ...,
    params: List[str] = ...,
    groups: List[str] = ...,
    outputs: List[str] = ...,
    method: str = ...,
    trajectories: int = ...,
    range: Optional[float] = ...,
    seed: int = ...,
    jobs: Optional[int] = ...,
) -> str: ...
