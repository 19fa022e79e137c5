"""Type stubs of greybox's native module (PyO3). Use the ``greybox`` package's wrappers: they
take any array-like (``numpy.typing.ArrayLike``) and hand these functions contiguous float64
arrays. Long calls run on a worker thread and raise ``KeyboardInterrupt`` on Ctrl-C."""

from typing import Any, Callable, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

__version__: str

from ._errors import GreyboxError as GreyboxError

# this thread's progress callback and provenance command for its next calls; the previous pair
def swap_call(progress: Optional[Callable[[str, int, Optional[int]], Any]] = None, command: Optional[Sequence[str]] = None) -> Tuple[Any, Any]: ...
# the law file at path and the model files and tables it names
def law_files(path: str) -> list[Any]: ...

# value, low, high, in_domain, and the outside-domain warning (None when all points lie inside)
_Arrays = Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.bool_], Optional[str]]

class Model:
    @staticmethod
    def load(path: str) -> "Model": ...
    @staticmethod
    def from_json(text: str) -> "Model": ...
    def to_json(self) -> str: ...
    def save(self, path: str) -> None: ...
    @property
    def family(self) -> str: ...
    @property
    def features(self) -> list[str]: ...
    @property
    def units(self) -> list[str]: ...
    @property
    def target(self) -> str: ...
    @property
    def training_domain(self) -> list[tuple[float, float]]: ...
    @property
    def interval_json(self) -> str: ...
    @property
    def hyperparameters_json(self) -> str: ...
    @property
    def held_out_r2(self) -> Optional[float]: ...
    @property
    def content_hash(self) -> str: ...
    def predict(self, x: npt.NDArray[np.float64], outside: str = "warn", margin: float = 0.05) -> _Arrays: ...
    def mu(
        self,
        pressure_pa: npt.NDArray[np.float64],
        velocity_m_s: npt.NDArray[np.float64],
        temperature_k: Optional[npt.NDArray[np.float64]] = None,
        outside: str = "warn",
        margin: float = 0.05,
    ) -> _Arrays: ...

class Law:
    @staticmethod
    def load(path: str) -> "Law": ...
    @staticmethod
    def from_model(model: Model) -> "Law": ...
    @property
    def name(self) -> str: ...
    @property
    def domain_json(self) -> Optional[str]: ...
    def mu(
        self,
        pressure_pa: npt.NDArray[np.float64],
        velocity_m_s: npt.NDArray[np.float64],
        temperature_k: Optional[npt.NDArray[np.float64]] = None,
        outside: str = "warn",
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_], Optional[str]]: ...

def hertz_rows(
    normal_force_n: npt.NDArray[np.float64],
    radius_mm: float,
    e1_gpa: float,
    nu1: float,
    e2_gpa: float,
    nu2: float,
    length_mm: Optional[float] = None,
    convention: str = "textbook-max",
) -> str: ...
def synth(
    out: str,
    study: Optional[str] = None,
    formats: Sequence[str] = ...,
    normal_force_count: Optional[int] = None,
    velocity_count: Optional[int] = None,
    force: bool = False,
) -> str: ...
def read_recording(path: str, study: Optional[str] = None, channels: Optional[str] = None) -> dict: ...
def identify(
    recordings: Sequence[str],
    dataset: str,
    study: Optional[str] = None,
    use_plan: bool = False,
    truth: Optional[str] = None,
    track_radii_mm: Sequence[float] | npt.NDArray[np.float64] = ...,
    normal_force_count: Optional[int] = None,
    velocity_count: Optional[int] = None,
    settings: Optional[str] = None,
    channels: Optional[str] = None,
) -> str: ...
def ploughing_correction(settings: str) -> str: ...
def simulate_pin(settings: str, output: str) -> str: ...
def couple(settings: str) -> str: ...
def fit_models(data: str, out: str, target: Optional[str] = None, features: Optional[Sequence[str]] = None, config: Optional[str] = None, force: bool = False) -> str: ...
def grey_box_law(
    model: str,
    out: str,
    blend_fraction: float = 0.1,
    clamp: Optional[tuple[float, float]] = (0.05, 1.0),
    shear_cap_k_mpa: Optional[float] = None,
) -> str: ...
def export_table(law: str, format: str, out: str, options: str = "{}") -> str:
    """Export `law` as `format`; `options`: JSON of the overrides (library names, SI)."""
    ...

def export_defaults(format: str) -> str:
    """JSON of the default export options of `format`."""
    ...

def simulate_cut(setup: str, out: str, law: Optional[str] = None, fraction: float = 1.0, force: bool = False, frames: int = 0) -> str: ...
def report(study_dir: str, out: Optional[str] = None) -> str: ...
def example(name: str) -> str: ...
def import_model(
    source: str,
    features: Optional[Sequence[str]] = None,
    target: str = "cof_adhesive",
    domain: Optional[Sequence[tuple[float, float]]] = None,
    x_train: Optional[npt.NDArray[np.float64]] = None,
    x_cal: Optional[npt.NDArray[np.float64]] = None,
    y_cal: Optional[npt.NDArray[np.float64]] = None,
    coverage: float = 0.95,
    is_json: bool = False,
    contact_json: Optional[str] = None,
    contact_study: Optional[str] = None,
) -> Model: ...
