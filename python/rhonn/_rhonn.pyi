"""Type stubs of the Rust extension ``rhonn._rhonn`` (use the ``rhonn`` package's API)."""

from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

__version__: str

def run(
    name: str, toml_text: Optional[str] = None, out: Optional[str] = None
) -> Tuple[Dict[str, npt.NDArray[np.float64]], Optional[Dict[str, npt.NDArray[np.float64]]], str]: ...
def fit(
    us: List[npt.NDArray[np.float64]],
    ys: List[npt.NDArray[np.float64]],
    dt: float,
    inputs: List[str],
    outputs: List[str],
    spec_toml: Optional[str] = None,
    spec_source: str = "the model spec",
    select: bool = False,
    select_steps_ahead: Optional[int] = None,
    time_budget_s: Optional[float] = None,
) -> Model: ...
def campaign(
    name: str,
    runs: int,
    seed: int,
    out: str,
    toml_text: Optional[str] = None,
    threads: Optional[int] = None,
    corners: bool = False,
    envelope_runs: int = 1000,
) -> str: ...
def scenarios() -> List[Tuple[str, str]]: ...
def show(name: str) -> str: ...
def json_to_toml(json: str) -> str: ...
def load(path: str) -> Model: ...
def _rust_run_seconds(name: str, repeats: int) -> float: ...

class Model:
    _info: Tuple[str, List[str], List[str], float, Optional[str], List[str]]
    def _predict(
        self,
        u: npt.NDArray[np.float64],
        y: npt.NDArray[np.float64],
        steps_ahead: Optional[int] = None,
        baseline: bool = False,
        init_window: Optional[int] = None,
    ) -> Tuple[npt.NDArray[np.float64], str, List[str]]: ...
    def save(self, path: str, force: bool = False) -> None: ...
    def to_json(self) -> str: ...
    @staticmethod
    def from_json(text: str) -> Model: ...

class OnlineIdentifier:
    weights: npt.NDArray[np.float64]
    term_names: List[str]
    notes: List[str]
    def __new__(
        cls,
        inputs: Sequence[str],
        outputs: Sequence[str],
        dt: float,
        model: Optional[str] = None,
        y_offset: Optional[Sequence[float]] = None,
        y_scale: Optional[Sequence[float]] = None,
        u_offset: Optional[Sequence[float]] = None,
        u_scale: Optional[Sequence[float]] = None,
        y_bounds: Optional[Sequence[Tuple[float, float]]] = None,
        samples: Optional[int] = None,
    ) -> OnlineIdentifier: ...
    _selection_json: Optional[str]
    def update(self, t: float, u: Any, y: Any) -> npt.NDArray[np.float64]: ...
    def freeze(self) -> Model: ...
    def resume(self) -> None: ...
    def reset(self) -> None: ...
    def _rust_seconds_per_update(
        self, t: npt.NDArray[np.float64], u: npt.NDArray[np.float64], y: npt.NDArray[np.float64]
    ) -> float: ...
