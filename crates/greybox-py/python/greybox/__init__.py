"""greybox: tribometer recordings to data-driven friction laws for metal-cutting simulation.

The Python face of the greybox Rust toolkit. The article's pipeline, end to end::

    import greybox as gb
    dataset, summary = gb.identify(["recordings/"], "dataset.csv")  # any rig's recordings
    adhesive, corr = gb.ploughing_correction("dataset.csv", "adhesive.csv")  # adhesive μ
    report = gb.fit("adhesive.csv", "fit/")                         # RF, SVR, boosting, MLP
    model = gb.load_model("fit/models/svr.json")
    mu = model.mu(pressure_Pa=[1.2e9], velocity_m_per_s=[2.0])      # with intervals
    gb.export_table(model, "abaqus", "friction.inp", pressure_Pa=..., velocity_m_per_s=...)
    cut = gb.simulate_cut("cut.toml", "cut/", law=model)

Models trained in scikit-learn or XGBoost come in through :func:`from_sklearn` and
:func:`from_xgboost`. Arrays in and out are NumPy arrays; tables are pandas DataFrames when
pandas is installed (``as_frame=None``), else dicts of arrays. Units are SI and named in
every argument (``pressure_Pa``, ``velocity_m_per_s``, ``temperature_K``). Errors are
:class:`GreyboxError` with the command line's message: :class:`InputError` (a
``ValueError``) for bad input — a wrong type or value of any argument too, naming the
argument — :class:`SettingsError` for refused settings, :class:`MissingFileError` (a
``FileNotFoundError``) for a missing file. Long calls release the GIL, stop on Ctrl-C
(``KeyboardInterrupt`` in the thread whose call was interrupted, leaving no half-written
output and other threads' calls running) and report progress when asked (``progress=``).
A :class:`Law` or :class:`Model` object goes wherever a law or model file does. Models and
laws pickle with their content.
"""

from __future__ import annotations

import functools
import inspect
import json
import os
import re
import tempfile
import warnings
from typing import Any, Callable, NamedTuple, Optional, Sequence, TypeVar, Union

import numpy as np
import numpy.typing as npt

from . import _calls, _native
from ._errors import GreyboxError, InputError, MissingFileError, SettingsError, UnusualValueWarning
from ._sklearn import export_sklearn, export_sklearn_json
from ._tables import read_csv, table

__version__: str = _native.__version__

PathLike = Union[str, "os.PathLike[str]"]

#: ``progress=`` of a long call: ``None`` (silent), ``True`` (log and bars) or a callable
#: ``progress(stage, done, total)`` (see :mod:`greybox._progress`; the wrapper of
#: :mod:`greybox._calls` takes it, the function's body never sees it).
Progress = Union[None, bool, Callable[[str, int, Optional[int]], Any]]

#: Numbers in an array: a NumPy array, a list, a tuple, a scalar (anything ``numpy.asarray``
#: turns into float64 numbers).
ArrayLike = npt.ArrayLike

__all__ = [
    "GreyboxError",
    "InputError",
    "SettingsError",
    "MissingFileError",
    "UnusualValueWarning",
    "DomainWarning",
    "Model",
    "Law",
    "Prediction",
    "LawValues",
    "hertz",
    "synth",
    "read_recording",
    "rig_profiles",
    "identify",
    "read_dataset",
    "ploughing_correction",
    "fit",
    "load_model",
    "load_law",
    "from_sklearn",
    "from_xgboost",
    "from_onnx",
    "import_model",
    "export_sklearn",
    "grey_box_law",
    "export_table",
    "export_defaults",
    "settings_defaults",
    "windows",
    "fit_flow_curves",
    "fit_rate_sensitivity",
    "simulate_cut",
    "validate",
    "simulate_pin",
    "couple",
    "report",
    "example",
    "budget",
    "set_budget",
]


def _asarray(x: Any, name: str) -> np.ndarray:
    """``x`` as a contiguous float64 array; an unconvertible value is an InputError naming
    the argument."""
    try:
        return np.ascontiguousarray(np.asarray(x, dtype=np.float64))
    except (TypeError, ValueError) as e:
        raise InputError(f"{name}: expected numbers, got {type(x).__name__} ({e})") from e


def _path(p: Any, name: str) -> str:
    """A path argument as a string; anything else is an InputError naming the argument."""
    try:
        # a path given as bytes (or whose __fspath__ gives bytes) decoded as the OS does
        return os.fsdecode(os.fspath(p))
    except TypeError as e:
        raise InputError(f"{name}: expected a path (str, bytes or os.PathLike), got {type(p).__name__}") from e


def _opt_path(p: Any, name: str) -> Optional[str]:
    return None if p is None else _path(p, name)


def _strs(x: Any, name: str) -> list:
    """A sequence of strings (a lone string is not one)."""
    if isinstance(x, str) or not all(isinstance(v, str) for v in _iterable(x, name)):
        raise InputError(f"{name}: expected a sequence of strings, got {x!r}")
    return list(x)


def _opt_str(x: Any, name: str) -> Optional[str]:
    """A string or None; anything else is an InputError naming the argument."""
    if x is not None and not isinstance(x, str):
        raise InputError(f"{name}: expected a string, got {type(x).__name__} {x!r}")
    return x


def _opt_float(x: Any, name: str) -> Optional[float]:
    """A number or None; anything else is an InputError naming the argument."""
    if x is None:
        return None
    if isinstance(x, bool) or not isinstance(x, (int, float, np.integer, np.floating)):
        raise InputError(f"{name}: expected a number, got {type(x).__name__} {x!r}")
    return float(x)


def _count(n: Any, name: str) -> Optional[int]:
    """A count (an int ≥ 0) or None, checked here because the native module's own refusals
    (OverflowError, a JSON type error) do not name the argument."""
    if n is None:
        return None
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)):
        raise InputError(f"{name}: expected a count (an integer ≥ 0), got {type(n).__name__} {n!r}")
    if n < 0:
        raise InputError(f"{name}: expected a count ≥ 0, got {n}")
    return int(n)


def _iterable(x: Any, name: str) -> list:
    try:
        return list(x)
    except TypeError as e:
        raise InputError(f"{name}: expected a sequence, got {type(x).__name__}") from e


def _pair(x: Any, name: str) -> tuple:
    """(a, b) of two numbers."""
    a = _asarray(x, name)
    if a.shape != (2,):
        raise InputError(f"{name}: expected (low, high), got {x!r}")
    return (float(a[0]), float(a[1]))


# pyo3 names a failed conversion as "argument 'name': why"
_NATIVE_ARGUMENT = re.compile(r"^argument '(\w+)': (.*)$", re.S)

# the native argument names that the public functions spell differently
_PUBLIC_NAMES = {
    "e1_gpa": "youngs_modulus_1_GPa",
    "nu1": "poisson_1",
    "e2_gpa": "youngs_modulus_2_GPa",
    "nu2": "poisson_2",
    "velocity_m_s": "velocity_m_per_s",
}

_F = TypeVar("_F", bound=Callable[..., Any])
_T = TypeVar("_T")


def _public_name(native: str, params: Sequence[str]) -> str:
    """The public spelling of a native argument name (case aside, or by the table above)."""
    for p in params:
        if p.lower() == native.lower():
            return p
    return _PUBLIC_NAMES.get(native, native)


def _argument_errors(f: _F) -> _F:
    """Wrap a public function or method: a wrong type or value of an argument, found when the
    native module converts it (pyo3 raises TypeError or OverflowError, e.g. a string for a
    float or a negative count), becomes an InputError naming the argument."""
    params = list(inspect.signature(f).parameters)

    @functools.wraps(f)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return f(*args, **kwargs)
        except (TypeError, OverflowError) as e:
            m = _NATIVE_ARGUMENT.match(str(e))
            if m is None:
                raise
            raise InputError(f"{_public_name(m.group(1), params)}: {m.group(2)}") from e

    return wrapper  # type: ignore[return-value]


class DomainWarning(UserWarning):
    """Points lie outside a model's training domain (widened by the margin) or a law's
    validity domain: the values there are extrapolations. Emitted by ``outside="warn"``."""


def _warn_outside(result: tuple) -> tuple:
    """The arrays of a native evaluation, warning (:class:`DomainWarning`) when its last
    element, the outside-domain message, is set."""
    *arrays, message = result
    if message is not None:
        warnings.warn(message, DomainWarning, stacklevel=4)
    return tuple(arrays)


def _f64(x: Any, name: str) -> np.ndarray:
    a = _asarray(x, name)
    if a.ndim == 0:
        a = a.reshape(1)
    if a.ndim != 1:
        raise InputError(f"{name}: expected a 1-D array, got shape {a.shape}")
    return a


def _f64_2d(x: Any, name: str) -> np.ndarray:
    a = _asarray(x, name)
    if a.ndim == 1:
        a = a.reshape(1, -1)
    if a.ndim != 2:
        raise InputError(f"{name}: expected a 2-D array (rows × features), got shape {a.shape}")
    return a


class Prediction(NamedTuple):
    """Model predictions: the value, the prediction interval (low, high) and whether each
    point lies in the training domain (widened by the margin)."""

    value: np.ndarray
    low: np.ndarray
    high: np.ndarray
    in_domain: np.ndarray


class LawValues(NamedTuple):
    """Friction coefficients of a law and whether each state lies in its validity domain."""

    mu: np.ndarray
    in_domain: np.ndarray


def _domain_check(outside: Optional[str], margin: Optional[float]) -> str:
    """``outside`` and ``margin`` as the library's domain check (``None``: its default)."""
    return _settings({"outside": _opt_str(outside, "outside"), "margin": _opt_float(margin, "margin")})


class Model:
    """A greybox model file: features with units, training domain, prediction interval.

    Load one with :func:`load_model`, or make one with :func:`from_sklearn` /
    :func:`from_xgboost`.
    """

    def __init__(self, native: "_native.Model"):
        self._m = native

    @property
    def family(self) -> str:
        """random-forest, svr, gradient-boosting or mlp."""
        return self._m.family

    @property
    def features(self) -> list:
        """Feature names (their suffixes give the units)."""
        return self._m.features

    @property
    def units(self) -> list:
        """The unit of each feature."""
        return self._m.units

    @property
    def target(self) -> str:
        return self._m.target

    @property
    def training_domain(self) -> list:
        """Per feature, (min, max) of the training data."""
        return self._m.training_domain

    @property
    def interval(self) -> dict:
        """The prediction interval: coverage, half_width, method."""
        return json.loads(self._m.interval_json)

    @property
    def hyperparameters(self) -> dict:
        """Selected hyperparameters, or where an imported model came from."""
        return json.loads(self._m.hyperparameters_json)

    @property
    def held_out_r2(self) -> Optional[float]:
        return self._m.held_out_r2

    @property
    def content_hash(self) -> str:
        return self._m.content_hash

    def predict(self, X: ArrayLike, outside: Optional[str] = None, margin: Optional[float] = None) -> Prediction:
        """Predictions at rows of ``X`` (n × features, in the features' units).

        ``outside="refuse"`` raises for points beyond the training domain widened by
        ``margin`` × each feature's range; ``"warn"`` (the default) predicts, flags them in
        ``in_domain`` and warns (:class:`DomainWarning`) how many lie outside, on which
        features. ``None`` takes the library's default, as ``greybox predict`` does
        (``settings_defaults("predict")``: warn, margin 0.05).
        A DataFrame is reordered to the model's feature names.
        """
        if hasattr(X, "columns"):
            missing = [f for f in self.features if f not in X.columns]
            if missing:
                raise InputError(f"X lacks the model's feature columns {missing}")
            X = X[self.features].to_numpy()  # type: ignore[index]
        return Prediction(*_warn_outside(self._m.predict(_f64_2d(X, "X"), _domain_check(outside, margin))))

    def mu(
        self,
        pressure_Pa: ArrayLike,
        velocity_m_per_s: ArrayLike,
        temperature_K: Optional[ArrayLike] = None,
        outside: Optional[str] = None,
        margin: Optional[float] = None,
    ) -> Prediction:
        """μ at contact states in SI, mapped to the model's feature units (a normal-force
        feature through the training contact's Hertz relation), with intervals and the
        domain check (``outside`` and ``margin`` as in :meth:`predict`). The states broadcast
        as in NumPy (a scalar pressure with an array of velocities, a grid from a column and
        a row); each array returned has the broadcast shape."""
        shape, (p, v, t) = _broadcast(pressure_Pa=pressure_Pa, velocity_m_per_s=velocity_m_per_s, temperature_K=temperature_K)
        return Prediction(*(a.reshape(shape) for a in _warn_outside(self._m.mu(p, v, t, _domain_check(outside, margin)))))

    def law(self) -> "Law":
        """This model as a friction law."""
        return Law(_native.Law.from_model(self._m), ("model.json", {"model.json": self.to_json().encode()}))

    def save(self, path: PathLike) -> None:
        """Write the model file (atomically)."""
        self._m.save(_path(path, "path"))

    def _write_into(self, folder: str) -> str:
        """The model file written into ``folder`` (for a call taking a model or law file),
        named after the object, so that a provenance record that lists it says what it was
        (a ``greybox.Model`` passed in Python, its content hash) rather than a bare temporary
        file."""
        path = os.path.join(folder, f"python-object-greybox.Model-{self.family}-{self.content_hash[:12]}.json")
        self.save(path)
        return path

    def to_json(self) -> str:
        """The model file's JSON text (what :meth:`save` writes)."""
        return self._m.to_json()

    @staticmethod
    def from_json(text: str) -> "Model":
        """A model from the JSON text of a model file (verified as :func:`load_model` does)."""
        return Model(_native.Model.from_json(text))

    def __reduce__(self) -> tuple:
        # pickled as the model file's text: the unpickled model predicts bit for bit the same
        return (_model_from_json, (self.to_json(),))

    def __repr__(self) -> str:
        return repr(self._m)


class Law:
    """A friction law: a law file, a model or a surrogate table.

    A law keeps the bytes of the files it was loaded from (the law file and the model files
    and tables it names by relative path): it pickles with that content, and a call taking a
    law file gets a copy of it, so neither depends on what the files hold later."""

    def __init__(self, native: "_native.Law", files: Optional[tuple] = None):
        self._l = native
        # (the law file's relative name, {relative name: bytes}), or None (nothing to write)
        self._files = files

    def __reduce__(self) -> tuple:
        if self._files is None:
            raise InputError(f"{self!r} cannot be pickled: it was made without a model or a file")
        return (_law_from_files, self._files)

    def _write_into(self, folder: str) -> str:
        """The law's files written into ``folder``, in their relative places: the law file's
        path (for a call taking a law file)."""
        if self._files is None:
            raise InputError(f"law: {self!r} has no file to pass on (made without a model or a file)")
        return _write_files(folder, *self._files)

    @property
    def name(self) -> str:
        return self._l.name

    @property
    def domain(self) -> Optional[dict]:
        """Ranges of pressure_pa, sliding_velocity_m_s (and temperature_k) the law is valid
        for, or None."""
        d = self._l.domain_json
        return None if d is None else json.loads(d)

    def mu(
        self,
        pressure_Pa: ArrayLike,
        velocity_m_per_s: ArrayLike,
        temperature_K: Optional[ArrayLike] = None,
        outside: Optional[str] = None,
    ) -> LawValues:
        """μ at contact states in SI (Pa, m/s, K). States outside the law's validity domain
        are flagged in ``in_domain``; ``outside="warn"`` (the default) also warns (:class:`DomainWarning`),
        ``"refuse"`` raises. The states broadcast as in NumPy; each array returned has the
        broadcast shape."""
        shape, (p, v, t) = _broadcast(pressure_Pa=pressure_Pa, velocity_m_per_s=velocity_m_per_s, temperature_K=temperature_K)
        return LawValues(*(a.reshape(shape) for a in _warn_outside(self._l.mu(p, v, t, _opt_str(outside, "outside")))))

    def __repr__(self) -> str:
        return repr(self._l)


def _model_from_json(text: str) -> Model:
    """Unpickling of a :class:`Model`."""
    return Model.from_json(text)


def _broadcast(**arrays: Any) -> tuple:
    """The broadcast shape of the named arrays (None left out) and each as a flat float64
    array of that shape's size (None stays None); shapes that do not broadcast are an
    InputError naming the arguments."""
    # (_asarray makes a scalar 1-D; a scalar's shape here is ())
    given = {k: _asarray(v, k).reshape(np.shape(v)) for k, v in arrays.items() if v is not None}
    try:
        shape = np.broadcast_shapes(*(a.shape for a in given.values()))
    except ValueError:
        shapes = ", ".join(f"{k} {a.shape}" for k, a in given.items())
        raise InputError(f"{', '.join(given)}: shapes do not broadcast ({shapes})") from None
    flat = {k: np.ascontiguousarray(np.broadcast_to(a, shape).ravel()) for k, a in given.items()}
    return shape, tuple(flat.get(k) for k in arrays)


def _write_files(folder: str, main: str, files: dict) -> str:
    """A law's files (``{relative name: bytes}``) written into ``folder`` in their relative
    places: the path of the law file ``main``."""
    # a file named as ../x lies above the law file's folder: put the law file deeper
    up = max((os.path.normpath(n).split(os.sep).count(os.pardir) for n in files), default=0)
    root = os.path.join(folder, *(["_"] * up))
    for name, data in files.items():
        p = os.path.normpath(os.path.join(root, name))
        os.makedirs(os.path.dirname(p), exist_ok=True)
        with open(p, "wb") as f:
            f.write(data)
    return os.path.join(root, main)


def _law_from_files(main: str, files: dict) -> Law:
    """Unpickling of a :class:`Law`: its files written into a temporary folder and loaded."""
    with tempfile.TemporaryDirectory() as d:
        return Law(_native.Law.load(_write_files(d, main, files)), (main, files))


def _law_from_origin(kind: str, what: str) -> Law:
    """Unpickling of a :class:`Law` pickled by an earlier version: a model's text or a path."""
    if kind == "model":
        return Model.from_json(what).law()
    return load_law(what)


def load_model(path: PathLike) -> Model:
    """Load and verify a greybox model file (schema, content hash, structure)."""
    return Model(_native.Model.load(_path(path, "path")))


def load_law(path: PathLike) -> Law:
    """Load a law file, model file or surrogate table as a friction law."""
    p = os.path.abspath(_path(path, "path"))
    base = os.path.dirname(p)
    files = {}
    for f in _native.law_files(p):
        files[os.path.relpath(f, base)] = _native.read_input(f, "law's file")
    return Law(_native.Law.load(p), (os.path.basename(p), files))


def hertz(
    normal_force_N: ArrayLike,
    *,
    radius_mm: Optional[float] = None,
    geometry: Optional[str] = None,
    length_mm: Optional[float] = None,
    e1_GPa: Optional[float] = None,
    nu1: Optional[float] = None,
    e2_GPa: Optional[float] = None,
    nu2: Optional[float] = None,
    convention: Optional[str] = None,
    as_frame: Optional[bool] = None,
) -> Any:
    """Hertz contact of a sphere (or a ``geometry="cylinder"`` of ``length_mm``) on a flat,
    per normal force, as ``greybox hertz``: contact half-width, maximum and mean pressure,
    approach, and the pressure under ``convention`` (textbook-max, textbook-mean,
    article-eq7). The settings and their defaults are the library's (``None``: the default:
    the article's 17 mm WC-Co pin, E 650 GPa, on steel, E 210 GPa, ν 0.3); ``inf`` modulus:
    rigid."""
    out = json.loads(_native.hertz_rows(_settings({
        "force_N": _f64(normal_force_N, "normal_force_N").ravel().tolist(),
        "radius_mm": radius_mm, "geometry": geometry, "length_mm": length_mm,
        "e1_GPa": e1_GPa, "nu1": nu1, "e2_GPa": e2_GPa, "nu2": nu2, "convention": convention,
    })))
    rows = out["rows"]
    cols = {k: [r[k] for r in rows] for k in (rows[0] if rows else {})}
    cols = {k: (v if k == "convention" else np.array([np.nan if x is None else x for x in v], dtype=float)) for k, v in cols.items()}
    return table(cols, as_frame)


def read_dataset(path: PathLike, as_frame: Optional[bool] = None) -> Any:
    """A friction dataset CSV as a table."""
    return read_csv(_path(path, "path"), as_frame)


def synth(
    out: Optional[PathLike] = None,
    *,
    study: Optional[PathLike] = None,
    format: Optional[str] = None,
    seed: Optional[int] = None,
    disturbance_scale: Optional[float] = None,
    force: bool = False,
    progress: Progress = None,
    **plan: Any,
) -> dict:
    """The virtual tribometer, as ``greybox synth``: a study's campaign (default: the
    bundled example study, the article's campaign) simulated into raw recordings (``format`` ``"csv"``,
    ``"tdms"`` or ``"both"``) and ``ground_truth.csv`` in ``out`` (default ``synth-out``).
    ``plan`` takes the ``[plan]`` overrides by the library's names
    (``normal_force_count=2``, ``velocity_max_m_per_min=200``, see ``settings_defaults("plan")``).
    Returns the summary dict."""
    return json.loads(_native.synth(_settings({
        "out": out, "study": study, "format": format, "seed": seed,
        "disturbance_scale": disturbance_scale, "force": force or None, **plan,
    })))


def rig_profiles() -> list:
    """The rig profiles ``rig=`` names (as ``greybox identify --list-rigs`` prints them): one
    dict per profile with ``name``, ``vendor`` (rig and export program), ``mode``
    (continuous, stepped or reciprocating) and ``verified_against`` (the real public export it was
    written against)."""
    return json.loads(_native.rig_profiles())


def read_recording(
    path: PathLike,
    study: Optional[PathLike] = None,
    channels: Optional[dict] = None,
    as_frame: Optional[bool] = None,
) -> tuple:
    """One raw recording of any supported rig format (delimited text in any dialect, TDMS,
    spreadsheets), its channels found by name or by ``channels`` (the study's
    ``[recording]`` settings as a dict, e.g. ``{"normal": {"name": "Fz", "unit": "N"}}``).
    Returns (table of the channels in SI: time_s, normal_force_N, tangential_force_N, …;
    how the file was read, as a dict)."""
    d = _native.read_recording(
        _path(path, "path"),
        _opt_path(study, "study"),
        None if channels is None else _dumps(channels),
    )
    how = json.loads(d.pop("how_read"))
    return table(d, as_frame), how


def identify(
    recordings: Union[PathLike, Sequence[PathLike]],
    out: Optional[PathLike] = None,
    *,
    as_frame: Optional[bool] = None,
    study: Optional[PathLike] = None,
    no_plan: bool = False,
    plan_steps: Optional[PathLike] = None,
    format: Optional[str] = None,
    track_radii_mm: Optional[ArrayLike] = None,
    truth: Optional[PathLike] = None,
    inspect: bool = False,
    inspect_dir: Optional[PathLike] = None,
    segment: Optional[str] = None,
    test_mode: Optional[str] = None,
    align: Optional[str] = None,
    steady: Optional[str] = None,
    settle_time_s: Optional[float] = None,
    map: Optional[Sequence[str]] = None,
    header_line: Optional[int] = None,
    sample_rate_hz: Optional[float] = None,
    columns: Optional[Sequence[str]] = None,
    rig: Optional[str] = None,
    constant_normal_force_N: Optional[float] = None,
    constant_sliding_velocity_m_per_s: Optional[float] = None,
    sheet: Optional[str] = None,
    tdms_group: Optional[str] = None,
    convention: Optional[str] = None,
    progress: Progress = None,
    **plan: Any,
) -> tuple:
    """Identify apparent friction coefficients per plateau from recordings of any supported
    rig (files or directories) into the dataset CSV ``out`` (default ``dataset.csv``), as
    ``greybox identify`` with the same settings and defaults; returns (dataset table,
    summary dict).

    Nothing is assumed behind your back: without ``study`` the contact takes the library's
    default convention (textbook-max) and loads and speeds come from the recordings. A study
    with a ``[plan]`` (or a load or velocity range in ``plan``: ``normal_force_count``,
    ``velocity_min_m_per_min``, …, ``track_radius_mm``) is matched to the recordings unless
    ``no_plan``; ``plan_steps`` is a CSV of the steps run (pin, normal_force_N,
    sliding_velocity_m_per_min). ``steady``: ``"auto"`` (after run-in, ASTM G99 practice),
    ``"last:50%"`` or ``"from:300s"``. ``map``: channel mappings
    ``["normal=Load:N", "radius=Radius:mm"]``, ``"normal=#2:N"`` by column number;
    ``columns`` names a headerless log's columns in order, units in the names
    (``["t_s", "Fn_N", "Ft_N"]``). ``inspect`` writes an SVG per recording with the steady
    windows shaded into ``inspect_dir``. Every setting is the library's
    ``IdentifySettings`` field of the same name (``None``: its default)."""
    if isinstance(recordings, (str, os.PathLike)):
        recordings = [recordings]
    summary = json.loads(_native.identify(_settings({
        "recordings": _iterable(recordings, "recordings"), "out": out, "study": study,
        "no_plan": no_plan or None, "plan_steps": plan_steps, "format": format,
        "track_radii_mm": None if track_radii_mm is None else _f64(track_radii_mm, "track_radii_mm").ravel().tolist(),
        "truth": truth, "inspect": inspect or None, "inspect_dir": inspect_dir,
        "segment": segment, "test_mode": test_mode, "align": align, "steady": steady,
        "settle_time_s": settle_time_s, "map": map, "header_line": header_line,
        "sample_rate_hz": sample_rate_hz, "columns": columns, "rig": rig,
        "constant_normal_force_N": constant_normal_force_N,
        "constant_sliding_velocity_m_per_s": constant_sliding_velocity_m_per_s,
        "sheet": sheet, "tdms_group": tdms_group, "convention": convention, **plan,
    })))
    return read_csv(summary["dataset"], as_frame), summary


def _json_value(x: Any) -> Any:
    """A path, NumPy scalar or array as JSON (for :func:`_settings`)."""
    if isinstance(x, os.PathLike):
        return os.fspath(x)
    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, np.generic):
        return x.item()
    raise InputError(f"settings: {type(x).__name__} {x!r} is not a number, text, path or list")


def _non_finite(x: Any, where: str) -> Optional[str]:
    """Where the first NaN or infinity inside ``x`` (numbers, lists, dicts, arrays) is."""
    if isinstance(x, (float, np.floating)) and not np.isfinite(x):
        return f"{where}: {x}"
    if isinstance(x, np.ndarray) and x.dtype.kind == "f":
        bad = np.flatnonzero(~np.isfinite(x))
        return f"{where}[{bad[0]}]: {x.flat[bad[0]]}" if bad.size else None
    if isinstance(x, dict):
        return next((w for k, v in x.items() if (w := _non_finite(v, k if not where else f"{where}.{k}"))), None)
    if isinstance(x, (list, tuple)):
        return next((w for i, v in enumerate(x) if (w := _non_finite(v, f"{where}[{i}]"))), None)
    return None


def _dumps(values: Any) -> str:
    """JSON for the library: a NaN or infinity (which JSON cannot hold) is an
    :class:`InputError` naming the argument and the element, never "not JSON"."""
    bad = _non_finite(values, "")
    if bad is not None:
        raise InputError(f"{bad} is not a finite number (NaN and infinity are not values greybox can use)")
    return json.dumps(values, default=_json_value, allow_nan=False)


def _settings(values: dict) -> str:
    """Keyword arguments as the library's settings JSON; ``None`` keeps the library's default.
    The library checks every value and names the key of a wrong one."""
    return _dumps({k: v for k, v in values.items() if v is not None})


def ploughing_correction(
    data: PathLike,
    out: PathLike,
    pin_radius_mm: Optional[float] = None,
    track_widths_csv: Optional[PathLike] = None,
    as_frame: Optional[bool] = None,
    *,
    method: Optional[str] = None,
    track_width: Optional[Sequence[Any]] = None,
    sim_loads: Optional[int] = None,
    sim_spacing_um: Optional[float] = None,
    sim_slide_mm: Optional[float] = None,
    sim_height_mm: Optional[float] = None,
    sim_tolerance: Optional[float] = None,
    sim_max_runs: Optional[int] = None,
    sim3d_loads: Optional[int] = None,
    sim3d_load_stride: Optional[int] = None,
    sim3d_elements_per_radius: Optional[float] = None,
    sim3d_slide_per_radius: Optional[float] = None,
    sim3d_increments: Optional[int] = None,
    ccx: Optional[PathLike] = None,
    progress: Progress = None,
) -> tuple:
    """The ploughing correction (adhesive μ) of a dataset into ``out``; returns (dataset
    table with ``cof_adhesive``, correction dict). ``method`` is ``"analytic"`` (Bowden–Tabor
    sphere ploughing, the default), ``"simulation"`` (inverse pin sliding in plane strain,
    with the ``sim_*`` settings) or ``"simulation-3d"`` (the article's inverse route on a 3D
    spherical pin in CalculiX, with ``sim_tolerance``, ``sim_max_runs``, the ``sim3d_*``
    settings and the ``ccx`` executable). Track widths: ``track_width`` as
    ``[(normal_force_N, width_um), …]`` (or ``"F:W"`` texts, as ``--track-width``) and/or a CSV (normal_force_N, track_width_um), else
    the article's Table 3. The settings and their defaults are ``greybox adhesive``'s, by the
    library's names (``None``: the default)."""
    widths = None
    if track_width is not None:
        widths = [t if isinstance(t, str) else "{!r}:{!r}".format(*map(float, _pair(t, "track_width")))
                  for t in _iterable(track_width, "track_width")]
    settings = {
        "data": _path(data, "data"),
        "out": _path(out, "out"),
        "method": _opt_str(method, "method"),
        "pin_radius_mm": _opt_float(pin_radius_mm, "pin_radius_mm"),
        "track_widths_csv": _opt_path(track_widths_csv, "track_widths_csv"),
        "track_width": widths,
        "sim_loads": _count(sim_loads, "sim_loads"),
        "sim_spacing_um": _opt_float(sim_spacing_um, "sim_spacing_um"),
        "sim_slide_mm": _opt_float(sim_slide_mm, "sim_slide_mm"),
        "sim_height_mm": _opt_float(sim_height_mm, "sim_height_mm"),
        "sim_tolerance": _opt_float(sim_tolerance, "sim_tolerance"),
        "sim_max_runs": _count(sim_max_runs, "sim_max_runs"),
        "sim3d_loads": _count(sim3d_loads, "sim3d_loads"),
        "sim3d_load_stride": _count(sim3d_load_stride, "sim3d_load_stride"),
        "sim3d_elements_per_radius": _opt_float(sim3d_elements_per_radius, "sim3d_elements_per_radius"),
        "sim3d_slide_per_radius": _opt_float(sim3d_slide_per_radius, "sim3d_slide_per_radius"),
        "sim3d_increments": _count(sim3d_increments, "sim3d_increments"),
        "ccx": _opt_path(ccx, "ccx"),
    }
    corr = json.loads(_native.ploughing_correction(_settings(settings)))
    return read_csv(out, as_frame), corr


def simulate_pin(
    out: PathLike,
    *,
    depth_um: Optional[float] = None,
    track_width_um: Optional[float] = None,
    pin_radius_mm: Optional[float] = None,
    mu: Optional[float] = None,
    spacing_um: Optional[float] = None,
    slide_mm: Optional[float] = None,
    height_mm: Optional[float] = None,
    speed_m_per_min: Optional[float] = None,
    mach: Optional[float] = None,
    mass_scaling: Optional[float] = None,
    max_particles: Optional[int] = None,
    force: bool = False,
    vtk_every: int = 0,
    checkpoint_every: int = 0,
    resume: Optional[PathLike] = None,
    frames: int = 0,
    progress: Progress = None,
) -> dict:
    """Press a rigid pin into a Johnson–Cook workpiece and slide it (plane strain), as
    ``greybox simulate pin``: give ``depth_um`` or a measured ``track_width_um``; the other
    settings default as on the command line (the article's 17 mm pin, μ 0.3, 10 µm
    particles, 150 m/min). Writes forces, windows, VTK and the summary into ``out``; returns
    the result (F_t/F_N, deformation share, …)."""
    settings = {
        "depth_um": _opt_float(depth_um, "depth_um"),
        "track_width_um": _opt_float(track_width_um, "track_width_um"),
        "pin_radius_mm": _opt_float(pin_radius_mm, "pin_radius_mm"),
        "mu": _opt_float(mu, "mu"),
        "spacing_um": _opt_float(spacing_um, "spacing_um"),
        "slide_mm": _opt_float(slide_mm, "slide_mm"),
        "height_mm": _opt_float(height_mm, "height_mm"),
        "speed_m_per_min": _opt_float(speed_m_per_min, "speed_m_per_min"),
        "mach": _opt_float(mach, "mach"),
        "mass_scaling": _opt_float(mass_scaling, "mass_scaling"),
        "max_particles": _count(max_particles, "max_particles"),
    }
    output = _run_output(out, force, vtk_every, checkpoint_every, resume, frames)
    return json.loads(_native.simulate_pin(_settings(settings), output))


def _run_output(out: Any, force: Any, vtk_every: Any, checkpoint_every: Any, resume: Any, frames: Any) -> str:
    """Where and how a simulation writes, as the library's run-output settings JSON (the
    same settings as the command line's ``--out``, ``--force``, ``--vtk-every``,
    ``--checkpoint-every``, ``--resume``, ``--frames``)."""
    return _settings({
        "out": _path(out, "out"),
        "force": bool(force),
        "vtk_every": _count(vtk_every, "vtk_every"),
        "checkpoint_every": _count(checkpoint_every, "checkpoint_every"),
        "resume": _opt_path(resume, "resume"),
        "frames": _count(frames, "frames"),
    })


def couple(
    law: PathLike,
    *,
    engine: Optional[str] = None,
    deck: Optional[PathLike] = None,
    segment: Optional[PathLike] = None,
    ccx: Optional[PathLike] = None,
    command: Optional[str] = None,
    windows: Optional[Sequence[str]] = None,
    work: Optional[PathLike] = None,
    max_cycles: Optional[int] = None,
    tol: Optional[float] = None,
    units: Optional[str] = None,
    segment_s: Optional[float] = None,
    progress: Progress = None,
) -> dict:
    """The restart loop with an external FE engine, as ``greybox couple``: ``engine``
    ``"calculix"`` (``deck``, ``segment``, ``ccx``, the deck's ``units`` ``"MPa-mm-s"``,
    ``"Pa-m-s"`` or ``"MPa-mm-ms"``) or ``"command"`` (``command``, ``windows``); per-window
    μ from ``law`` until every window's μ changes less than ``tol``. Returns the coupling
    result (cycles, μ per window, converged)."""
    settings = {
        "law": _path(law, "law"),
        "engine": _opt_str(engine, "engine"),
        "deck": _opt_path(deck, "deck"),
        "segment": _opt_path(segment, "segment"),
        "ccx": _opt_path(ccx, "ccx"),
        "command": _opt_str(command, "command"),
        "windows": None if windows is None else _strs(windows, "windows"),
        "work": _opt_path(work, "work"),
        "max_cycles": _count(max_cycles, "max_cycles"),
        "tol": _opt_float(tol, "tol"),
        "units": _opt_str(units, "units"),
        "segment_s": _opt_float(segment_s, "segment_s"),
    }
    return json.loads(_native.couple(_settings(settings)))


def fit(
    data: PathLike,
    out: Optional[PathLike] = None,
    *,
    target: Optional[str] = None,
    features: Optional[Sequence[str]] = None,
    study: Optional[PathLike] = None,
    families: Optional[Sequence[str]] = None,
    folds: Optional[int] = None,
    inner_folds: Optional[int] = None,
    fold_column: Optional[str] = None,
    seed: Optional[int] = None,
    bootstrap: Optional[int] = None,
    importance_repeats: Optional[int] = None,
    skip_nested: bool = False,
    rf_n_estimators: Optional[Sequence[int]] = None,
    svr_c: Optional[Sequence[float]] = None,
    svr_kernel: Optional[Sequence[str]] = None,
    svr_epsilon: Optional[Sequence[float]] = None,
    gb_n_estimators: Optional[Sequence[int]] = None,
    gb_max_depth: Optional[Sequence[int]] = None,
    gb_learning_rate: Optional[Sequence[float]] = None,
    mlp_hidden: Optional[Sequence[str]] = None,
    mlp_activation: Optional[Sequence[str]] = None,
    mlp_learning_rate: Optional[Sequence[float]] = None,
    mlp_max_epochs: Optional[int] = None,
    force: bool = False,
    progress: Progress = None,
) -> dict:
    """The article's learning protocol (grid search, nested cross-validation, bootstrap CIs,
    permutation importance, conformal intervals) on a dataset, as ``greybox fit`` with the
    same settings and defaults; model files, report and plots go into ``out`` (default
    ``fit-out``). ``target`` defaults to ``cof_adhesive`` where the dataset has it, else
    ``cof_apparent``; ``features`` to normal force and sliding velocity. ``study`` is a
    study TOML whose ``[fit]`` section the other settings override; ``fold_column`` an
    integer column of fold ids (grouped CV); grids by the flags' names (``mlp_hidden=["64x32",
    "32x16"]``, ``svr_kernel=["rbf"]``). A setting left at ``None`` takes the library's
    default, which ``settings_defaults("fit")`` lists: folds 5, inner_folds 5, seed 42,
    bootstrap 1000, importance_repeats 30 (the article's protocol), every family.
    Returns {"report", "outputs", "warnings"}."""
    return json.loads(_native.fit_models(_settings({
        "data": data, "out": out, "target": target, "features": features, "study": study,
        "families": families, "folds": folds, "inner_folds": inner_folds,
        "fold_column": fold_column, "seed": seed, "bootstrap": bootstrap,
        "importance_repeats": importance_repeats, "skip_nested": skip_nested or None,
        "rf_n_estimators": rf_n_estimators, "svr_c": svr_c, "svr_kernel": svr_kernel,
        "svr_epsilon": svr_epsilon, "gb_n_estimators": gb_n_estimators,
        "gb_max_depth": gb_max_depth, "gb_learning_rate": gb_learning_rate,
        "mlp_hidden": mlp_hidden, "mlp_activation": mlp_activation,
        "mlp_learning_rate": mlp_learning_rate, "mlp_max_epochs": mlp_max_epochs,
        "force": force or None,
    })))


def _contact(contact: Any) -> Any:
    """``contact=`` as settings JSON: a dict of the study's [contact] keys, or a study TOML."""
    if contact is None or isinstance(contact, dict):
        return contact
    if isinstance(contact, (str, os.PathLike)):
        return _path(contact, "contact")
    raise InputError(f"contact: expected a dict of the study's [contact] keys or a study TOML path, got {type(contact).__name__}")


_DATASET_CONTACT = ("pressure_convention", "hertz_pressure_MPa", "normal_force_N")


def _columns_of(x: Any) -> Optional[list]:
    """The column names of a DataFrame or a dict table, else None (an array)."""
    if hasattr(x, "columns"):
        return [str(c) for c in x.columns]
    if isinstance(x, dict):
        return list(x)
    return None


def _by_name(x: Any, features: Optional[Sequence[str]], name: str) -> Any:
    """A table's feature columns in the model's input order, taken by name (an array as is):
    reordered columns cannot swap a model's inputs."""
    cols = _columns_of(x)
    if cols is None:
        return _f64_2d(x, name)
    if features is None:
        raise InputError(f"{name}: a table's columns are taken by name: give features=[…] in the model's input order (its columns: {', '.join(cols)})")
    missing = [f for f in features if f not in cols]
    if missing:
        raise InputError(f"{name}: no column {', '.join(missing)} (its columns: {', '.join(cols)})")
    return _f64_2d(np.column_stack([np.asarray(x[f], dtype=float) for f in features]), name)


def _training_contact(x: Any) -> Optional[tuple]:
    """The friction dataset columns of a training table (gb.read_dataset), from which its
    contact is taken as ``greybox import --training-data`` takes it from the CSV."""
    cols = _columns_of(x)
    if cols is None or not all(c in cols for c in _DATASET_CONTACT):
        return None
    conv, p, f = (x[c] for c in _DATASET_CONTACT)
    return [str(c) for c in conv], np.asarray(p, dtype=float).tolist(), np.asarray(f, dtype=float).tolist()


def _import(source: str, is_json: bool, features, target, domain, X_train, X_cal, y_cal, coverage, contact, training_data=None, calibration=None) -> Model:
    if (X_cal is None) != (y_cal is None):
        raise InputError("X_cal, y_cal: calibration rows need both X_cal and y_cal")
    if features is None and X_train is not None and _columns_of(X_train) is not None and is_json:
        features = json.loads(source).get("feature_names")
    settings = _settings({
        "features": None if features is None else _strs(features, "features"),
        "target": _opt_str(target, "target"),
        "domain": None if domain is None else [[float(a), float(b)] for a, b in domain],
        "coverage": _opt_float(coverage, "coverage"),
        "contact": _contact(contact),
        "training_data": _opt_path(training_data, "training_data"),
        "calibration": _opt_path(calibration, "calibration"),
    })
    return Model(
        _native.import_model(
            source,
            is_json,
            settings,
            None if X_train is None else _by_name(X_train, features, "X_train"),
            None if X_cal is None else (_by_name(X_cal, features, "X_cal"), _f64(y_cal, "y_cal")),
            None if X_train is None else _training_contact(X_train),
        )
    )


def from_sklearn(
    estimator: Any,
    features: Optional[Sequence[str]] = None,
    target: Optional[str] = None,
    domain: Optional[Sequence[tuple]] = None,
    X_train: Any = None,
    X_cal: Any = None,
    y_cal: Any = None,
    coverage: Optional[float] = None,
    contact: Any = None,
    training_data: Optional[PathLike] = None,
    calibration: Optional[PathLike] = None,
) -> Model:
    """A fitted scikit-learn regressor as a greybox model: RandomForestRegressor,
    ExtraTreesRegressor, GradientBoostingRegressor, SVR (linear, poly, rbf, sigmoid) or
    MLPRegressor, optionally in a Pipeline behind StandardScaler/MinMaxScaler.

    ``features`` name the inputs with unit suffixes (default: ``feature_names_in_``). State
    the training domain as ``domain=[(min, max), …]`` or give ``X_train``. Rows the model
    was not trained on (``X_cal``, ``y_cal``) give a split-conformal interval. A DataFrame
    (or a dict table) is read by column name in the order of ``features``, never by
    position; ``training_data`` is the training CSV instead (as ``greybox import
    --training-data``); ``calibration`` a CSV of such rows with their target (as ``greybox
    import --calibration``). Training data that is a greybox friction dataset (the CSV, or its
    table from :func:`read_dataset`) also gives the model its contact, as on the command
    line. A feature set that cannot be a friction law μ(p, v[, T]) — no velocity, two
    force or pressure features — is refused here, naming what is missing.

    ``contact`` states the tribometer's pin contact, needed for a model trained on a normal
    force (``normal_force_N``) to be a friction law (:meth:`Model.law`, :meth:`Model.mu`,
    :func:`export_table`, :func:`simulate_cut`): a dict with the keys of a study's
    ``[contact]`` table (``convention`` — textbook-max, textbook-mean or article-eq7, the one
    the training pressures were computed with — required; ``pin_tip_radius_mm``,
    ``pin_youngs_modulus_gpa``, ``pin_poisson_ratio``, ``disk_youngs_modulus_gpa``,
    ``disk_poisson_ratio`` default to the article's pin), or a study TOML path whose
    ``[contact]`` table is taken, as ``greybox import --contact`` does. It is recorded in
    the model file. Feature names must carry a unit greybox maps (pressure ``_Pa``,
    ``_MPa``, ``_GPa``; velocity ``_m_per_s``, ``_m_per_min``; temperature ``_K``,
    ``_degC``; force ``_N``, ``_kN``); others are refused. Tree
    predictions agree with scikit-learn to rounding of the sum (splits bit-exact, including
    its float32 input cast); SVR and MLP to rounding."""
    exported = _foreign("estimator", "a fitted scikit-learn regressor or pipeline", lambda: export_sklearn_json(estimator))
    return _import(exported, True, features, target, domain, X_train, X_cal, y_cal, coverage, contact, training_data, calibration)


def _foreign(name: str, expected: str, call: Callable[[], _T]) -> _T:
    """``call`` on an object of another library: its own errors (an unfitted estimator, an
    object of the wrong kind: ``AttributeError``, ``TypeError``, ``ValueError``, XGBoost's
    and scikit-learn's own) become an :class:`InputError` naming the argument and what it
    should be."""
    try:
        return call()
    except GreyboxError:
        raise
    except (AttributeError, TypeError, ValueError, RuntimeError) as e:
        raise InputError(f"{name}: expected {expected}; {type(e).__name__}: {e}") from e


def from_xgboost(
    booster: Any,
    features: Optional[Sequence[str]] = None,
    target: Optional[str] = None,
    domain: Optional[Sequence[tuple]] = None,
    X_train: Any = None,
    X_cal: Any = None,
    y_cal: Any = None,
    coverage: Optional[float] = None,
    contact: Any = None,
    training_data: Optional[PathLike] = None,
    calibration: Optional[PathLike] = None,
) -> Model:
    """An XGBoost model (a ``Booster``, an ``XGBRegressor`` or a path to a booster saved as
    JSON or UBJSON) as a greybox model whose predictions equal ``Booster.predict`` bit for
    bit (float32 splits and float32 sums reproduced). Other arguments as in
    :func:`from_sklearn`."""
    if isinstance(booster, (str, os.PathLike)):
        return _import(_path(booster, "booster"), False, features, target, domain, X_train, X_cal, y_cal, coverage, contact, training_data, calibration)
    expected = "a fitted xgboost.Booster or XGBRegressor, or a path to a saved booster"
    b = _foreign("booster", expected, lambda: booster.get_booster() if hasattr(booster, "get_booster") else booster)
    if features is None and getattr(b, "feature_names", None):
        features = list(b.feature_names)
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "booster.ubj")
        _foreign("booster", expected, lambda: b.save_model(path))
        return _import(path, False, features, target, domain, X_train, X_cal, y_cal, coverage, contact, training_data, calibration)


def grey_box_law(
    model: PathLike,
    out: Optional[PathLike] = None,
    *,
    blend_fraction: Optional[float] = None,
    mu_min: Optional[float] = None,
    mu_max: Optional[float] = None,
    no_clamp: bool = False,
    shear_cap_k_MPa: Optional[float] = None,
    study: Optional[PathLike] = None,
) -> Law:
    """Write the grey-box law file ``out`` (default ``law.json``) around the model file
    ``model``, as ``greybox law`` with the same settings and defaults, and return it as a
    :class:`Law`: the learned model inside its training domain, a power law fitted to its
    training data outside, blended over ``blend_fraction`` (0.1) of each range; μ clamped to
    ``mu_min``..``mu_max`` (0.05..1.0) unless ``no_clamp``; Zorev's cap τ ≤ k when
    ``shear_cap_k_MPa`` is given (default: none, stated as ``null`` in the file); the contact
    of ``study``'s ``[contact]``, else the one the model recorded from its training data. A
    relative ``model`` path is resolved against the law file's folder, as the file records
    it."""
    settings = {
        "model": model, "out": out, "blend_fraction": blend_fraction, "mu_min": mu_min,
        "mu_max": mu_max, "no_clamp": no_clamp or None, "shear_cap_k_MPa": shear_cap_k_MPa,
        "study": study,
    }
    _native.grey_box_law(_settings(settings))
    return load_law(out if out is not None else _calls.library_default("law", "out"))


def import_model(
    path: PathLike,
    features: Optional[Sequence[str]] = None,
    target: Optional[str] = None,
    domain: Optional[Sequence[tuple]] = None,
    X_train: Optional[ArrayLike] = None,
    X_cal: Optional[ArrayLike] = None,
    y_cal: Optional[ArrayLike] = None,
    coverage: Optional[float] = None,
    contact: Any = None,
    training_data: Optional[PathLike] = None,
    calibration: Optional[PathLike] = None,
) -> Model:
    """A model file of another library, as ``greybox import`` reads it: an XGBoost booster
    (JSON/UBJSON), an ONNX model, or a scikit-learn export written from
    :func:`export_sklearn`. Other arguments as in :func:`from_sklearn`."""
    return _import(_path(path, "path"), False, features, target, domain, X_train, X_cal, y_cal, coverage, contact, training_data, calibration)


def from_onnx(
    model: Any,
    features: Sequence[str],
    target: Optional[str] = None,
    domain: Optional[Sequence[tuple]] = None,
    X_train: Any = None,
    X_cal: Any = None,
    y_cal: Any = None,
    coverage: Optional[float] = None,
    contact: Any = None,
    training_data: Optional[PathLike] = None,
    calibration: Optional[PathLike] = None,
) -> Model:
    """An ONNX model (a path, the file's bytes, or an ``onnx.ModelProto``) converted into a
    greybox model — tree ensembles (``TreeEnsembleRegressor``), SVMs (``SVMRegressor``),
    linear models and feed-forward networks (``MatMul``/``Gemm`` with ``Relu``, ``Tanh`` or
    ``Sigmoid``), behind ``Scaler`` or element-wise scaling; anything else is refused naming
    the operator. Tree splits are exact; sums, networks and SVMs agree with onnxruntime to
    float32 rounding (the runtime computes in float32). ONNX graphs carry no usable feature
    names: state ``features`` with units. Other arguments as in :func:`from_sklearn`."""
    if isinstance(model, (str, os.PathLike)):
        return _import(_path(model, "model"), False, features, target, domain, X_train, X_cal, y_cal, coverage, contact, training_data, calibration)
    data = model if isinstance(model, (bytes, bytearray)) else _foreign(
        "model", "a path, the bytes of an ONNX file or an onnx.ModelProto", lambda: model.SerializeToString())
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "model.onnx")
        with open(path, "wb") as f:
            f.write(data)
        return _import(path, False, features, target, domain, X_train, X_cal, y_cal, coverage, contact, training_data, calibration)


def _law_path(law: Any, tmp: str) -> str:
    """A path for a law given as a path, a Model or a Law (written into ``tmp``)."""
    if isinstance(law, (Law, Model)):
        return law._write_into(tmp)
    if isinstance(law, (str, os.PathLike)):
        return os.fspath(law)
    raise InputError(f"law: expected a path, a greybox.Law or a greybox.Model, got {type(law).__name__}")


def export_table(
    law: Any,
    format: str,
    out: PathLike,
    pressure_Pa: Optional[ArrayLike] = None,
    velocity_m_per_s: Optional[ArrayLike] = None,
    temperature_K: Optional[ArrayLike] = None,
    *,
    units: Optional[str] = None,
    temperature_unit: Optional[str] = None,
    taumax_Pa: Optional[float] = None,
    deform_reference_velocity_m_per_s: Optional[float] = None,
    deform_objects: Optional[Sequence[int]] = None,
    deform_windows: Optional[PathLike] = None,
    lsdyna_table_id: Optional[int] = None,
    check_points: Optional[int] = None,
    steps: Optional[str] = None,
    table_kind: Optional[str] = None,
    tolerance: Optional[float] = None,
    max_table_size: Optional[int] = None,
    adaptive_grid: Optional[bool] = None,
) -> dict:
    """Export a law (path or Model) as ``format`` — abaqus, deform, lsdyna, csv or table.

    Every option left at ``None`` takes the library's default for ``format``, the same as
    ``greybox export`` on the command line: ``export_defaults(format)`` lists them (the grid,
    the engine's unit system — ``"MPa-mm-s"``, ``"Pa-m-s"`` or ``"MPa-mm-ms"`` —, its
    temperature unit, DEFORM's objects and reference velocity, LS-DYNA's table id, the
    tolerance). Grid values and options are SI (``pressure_Pa``, ``velocity_m_per_s``,
    ``temperature_K``, ``taumax_Pa``); an option of another engine than ``format``'s is an
    error.

    Tree-ensemble laws get two table points at each split threshold (``steps="auto"``), so an
    engine interpolating linearly reproduces the model exactly; a surrogate table
    (``format="table"``) is exact for trees and refined to ``tolerance`` for smooth laws
    (``table_kind`` overrides). A table of more than ``max_table_size`` values is refused.
    Returns the export report: ``line`` (one-line description), ``max_deviation`` from the
    law on ``check_points`` states inside the grid, ``shape``, ``exact_steps``, ``bytes``,
    ``warnings`` (also issued as Python warnings), ``domain`` (for a law with a validity
    domain: the domain, ``grid_points`` and ``points_outside``, whose values are the law's
    extrapolation; any outside is also an :class:`UnusualValueWarning`, with the unit factor
    when the whole grid misses the domain — MPa numbers given as Pa)."""
    options: dict = {
        "units": _opt_str(units, "units"),
        "temperature_unit": _opt_str(temperature_unit, "temperature_unit"),
        "taumax_Pa": _opt_float(taumax_Pa, "taumax_Pa"),
        "deform_reference_velocity_m_per_s": _opt_float(deform_reference_velocity_m_per_s, "deform_reference_velocity_m_per_s"),
        "deform_objects": None if deform_objects is None else [_count(x, "deform_objects") for x in _iterable(deform_objects, "deform_objects")],
        "deform_windows": _opt_path(deform_windows, "deform_windows"),
        "lsdyna_table_id": _count(lsdyna_table_id, "lsdyna_table_id"),
        "check_points": _count(check_points, "check_points"),
        "steps": _opt_str(steps, "steps"),
        "table_kind": _opt_str(table_kind, "table_kind"),
        "tolerance": _opt_float(tolerance, "tolerance"),
        "max_table_size": _count(max_table_size, "max_table_size"),
        "adaptive_grid": adaptive_grid,
    }
    for name, values in (("pressure_Pa", pressure_Pa), ("velocity_m_per_s", velocity_m_per_s), ("temperature_K", temperature_K)):
        if values is not None:
            options[name] = [float(x) for x in _f64(values, name)]
    options = {k: v for k, v in options.items() if v is not None}
    with tempfile.TemporaryDirectory() as d:
        report = json.loads(_native.export_table(_law_path(law, d), format, _path(out, "out"), _dumps(options)))
    for w in report.get("warnings", []):
        warnings.warn(w, stacklevel=3)
    return report


def windows(
    mesh: PathLike,
    out: Optional[PathLike] = None,
    *,
    coating_set: Optional[str] = None,
    outward: Optional[float] = None,
    inward: Optional[float] = None,
    segment_length: Optional[float] = None,
    mu: Optional[float] = None,
    deform_objects: Optional[Sequence[int]] = None,
    force: bool = False,
) -> dict:
    """Friction windows from a coated tool mesh (Gmsh .msh or Abaqus .inp), as ``greybox
    windows`` with the same settings and defaults: windows.json, windows.csv, windows.vtk
    and windows_frcwin.key written into ``out`` (default ``windows-out``). Returns
    {"windows": [...], "nodes", "elements"}."""
    return json.loads(_native.windows(_settings({
        "mesh": mesh, "out": out, "coating_set": coating_set, "outward": outward,
        "inward": inward, "segment_length": segment_length, "mu": mu,
        "deform_objects": None if deform_objects is None else list(deform_objects),
        "force": force or None,
    })))


def fit_flow_curves(
    curves: PathLike,
    *,
    c: Optional[float] = None,
    ref_strain_rate_per_s: Optional[float] = None,
    room_temperature_C: Optional[float] = None,
    melt_temperature_K: Optional[float] = None,
    misfit_threshold: Optional[float] = None,
    out: Optional[PathLike] = None,
) -> dict:
    """Johnson–Cook A, B, n, m fitted to compression flow curves (CSV: strain, stress_MPa,
    temperature_C, strain_rate_per_s), as ``greybox material fit`` with the same settings
    and defaults; with ``out``, the fit is also written there as JSON. Returns the fit."""
    return json.loads(_native.fit_flow_curves(_settings({
        "curves": curves, "c": c, "ref_strain_rate_per_s": ref_strain_rate_per_s,
        "room_temperature_C": room_temperature_C, "melt_temperature_K": melt_temperature_K,
        "misfit_threshold": misfit_threshold, "out": out,
    })))


def fit_rate_sensitivity(
    config: PathLike,
    measured_force_N_per_mm: float,
    *,
    c_min: Optional[float] = None,
    c_max: Optional[float] = None,
    tolerance_N_per_mm: Optional[float] = None,
    max_runs: Optional[int] = None,
    out: Optional[PathLike] = None,
    progress: Progress = None,
) -> dict:
    """Johnson–Cook C such that the simulated steady cutting force of the set-up ``config``
    matches ``measured_force_N_per_mm``, as ``greybox material fit-c`` with the same settings
    and defaults (each run is a cutting simulation). Returns the search."""
    return json.loads(_native.fit_rate_sensitivity(_settings({
        "config": config, "measured_force_N_per_mm": measured_force_N_per_mm, "c_min": c_min,
        "c_max": c_max, "tolerance_N_per_mm": tolerance_N_per_mm, "max_runs": max_runs,
        "out": out,
    })))


def settings_defaults(stage: str) -> dict:
    """The library's settings of ``stage`` with their defaults: the keyword arguments of its
    function, which are the command line's flags by the library's field names. Stages:
    identify, synth, hertz, plan, fit, adhesive, pin, couple, law, windows, flow_curves,
    rate_sensitivity, cut (:func:`simulate_cut`), predict (:meth:`Model.predict`), import
    (:func:`import_model` and the other imports), and output (a run's output directory),
    validate, report."""
    return json.loads(_native.settings_defaults(stage))


def export_defaults(format: str) -> dict:
    """The library's default options of ``export_table(law, format, ...)``: the keyword
    arguments that format takes, with their defaults (SI)."""
    return json.loads(_native.export_defaults(format))


def simulate_cut(
    setup: PathLike,
    out: PathLike,
    law: Any = None,
    fraction: float = 1.0,
    force: bool = False,
    as_frame: Optional[bool] = None,
    frames: int = 0,
    *,
    vtk_every: int = 0,
    checkpoint_every: int = 0,
    resume: Optional[PathLike] = None,
    progress: Progress = None,
) -> dict:
    """Run greybox's 2D SPH orthogonal-cutting simulation of a set-up TOML into ``out``,
    with the set-up's friction or ``law`` (a law/model/table path or a Model). Returns the
    summary dict plus ``forces`` (force history) and ``contact_profile`` (along the rake
    face) tables. The chip's last state is drawn (``chip_temperature.svg``,
    ``chip_plastic_strain.svg``); ``frames`` > 0 also draws that many instants
    (``frames/chip_NNN.svg``). As ``greybox simulate cutting``: ``vtk_every`` writes VTK
    particle files every N steps (0: first and last), ``checkpoint_every`` a checkpoint every
    N steps (the run works in ``out.partial`` until complete), ``resume`` continues an
    interrupted run from its checkpoint (``out.partial/checkpoint.json``) with the outputs of
    an uninterrupted one."""
    output = _run_output(out, force, vtk_every, checkpoint_every, resume, frames)
    with tempfile.TemporaryDirectory() as d:
        summary = json.loads(
            _native.simulate_cut(
                _dumps(
                    {
                        "config": _path(setup, "setup"),
                        "law": None if law is None else _law_path(law, d),
                        "fraction": fraction,
                    }
                ),
                output,
            )
        )
    summary["forces"] = read_csv(os.path.join(os.fspath(out), "forces.csv"), as_frame)
    summary["contact_profile"] = read_csv(os.path.join(os.fspath(out), "contact_profile.csv"), as_frame)
    return summary


def validate(
    suite: Optional[PathLike] = None,
    out: Optional[PathLike] = None,
    *,
    only: Optional[Sequence[str]] = None,
    tool: Optional[Sequence[str]] = None,
    fraction: Optional[float] = None,
    force: Optional[bool] = None,
    executor: Optional[str] = None,
    jobs: Optional[int] = None,
    poll_s: Optional[float] = None,
    progress: Progress = None,
) -> dict:
    """The validation suite, as ``greybox bench validate``: the suite file's measured cuts
    simulated with each of its friction models (a calibrated constant μ, law files, laws with
    fitted parameters), each calibrated on the calibration conditions only and judged on the
    held-out ones; ``only`` limits the held-out conditions, ``tool`` the tool models
    (``"adiabatic"``, ``"thermal"``), ``fraction`` the cut length. Writes ``results.csv``,
    ``summary.json``, ``validation.md``, ``forces.svg`` into ``out``. The cuts run in this
    process unless ``executor`` is ``"local"`` (a pool of ``jobs`` processes) or ``"slurm"``
    (one array job per step, the suite's ``[slurm]`` resources, polled every ``poll_s``
    seconds), which start the ``greybox`` program on PATH per cut. Returns the results
    (``outcomes`` per cut with the local rake-face quantities, ``summaries`` per material,
    tool and friction model with their cost, ``fits``: every shape tried) and ``files``."""
    settings = {
        "suite": _opt_path(suite, "suite"),
        "out": _opt_path(out, "out"),
        "only": None if only is None else _strs(only, "only"),
        "tool": None if tool is None else _strs(tool, "tool"),
        "fraction": _opt_float(fraction, "fraction"),
        "force": force,
        "executor": _opt_str(executor, "executor"),
        "jobs": jobs,
        "poll_s": _opt_float(poll_s, "poll_s"),
    }
    r = json.loads(_native.validate(_settings(settings)))
    r["validation"]["files"] = r["files"]
    return r["validation"]


def example(name: str) -> str:
    """The text of a file bundled with greybox: ``"aisi1045-cut.toml"`` (the article's
    orthogonal cut, AISI 1045 at 150 m/min — a set-up for :func:`simulate_cut`) or
    ``"demo-study.toml"`` (the example study the stages use by default)."""
    return _native.example(name)


def budget() -> dict:
    """The readers' caps in force, by the library's names, in bytes, cells or elements
    (``max_input_bytes``, ``max_recording_bytes``, ``max_data_bytes``, …; the command line's
    ``--max-*`` global options)."""
    return json.loads(_native.swap_budget("{}"))


def set_budget(**caps: int) -> dict:
    """Sets the readers' caps named (``set_budget(max_data_bytes=8 << 30)``; the others kept)
    for the rest of the process, as the command line's ``--max-*`` options do; returns the
    caps before. A name that is no cap is a SettingsError listing the caps."""
    return json.loads(_native.swap_budget(_dumps(caps)))


def report(
    study_dir: PathLike,
    out: Optional[PathLike] = None,
    *,
    max_file_bytes: Optional[int] = None,
    max_svg_bytes: Optional[int] = None,
    max_header_bytes: Optional[int] = None,
    max_entries: Optional[int] = None,
    max_depth: Optional[int] = None,
    max_page_bytes: Optional[int] = None,
    progress: Progress = None,
) -> dict:
    """Write one self-contained HTML page for a study directory (default
    ``study_dir/report.html``): campaign, friction data, models, cuts with pictures of the
    chip, rig dynamics and wear, provenance; each section when its files are there. Returns
    the summary: ``path``, ``bytes``, ``sections``, ``figures``, ``warnings`` (files found
    but unreadable). The caps of a directory nobody vouches for are ``greybox report``'s
    (``settings_defaults("report")``): the largest file read whole (64 MiB), SVG turned into
    a figure (8 MiB), bytes read to find a CSV header (64 KiB), directory entries looked at
    (100 000), depth searched (6) and page written (64 MiB); a cap reached is a warning
    naming it."""
    return json.loads(_native.report(_settings({
        "study_dir": _path(study_dir, "study_dir"), "out": _opt_path(out, "out"),
        "max_file_bytes": _count(max_file_bytes, "max_file_bytes"),
        "max_svg_bytes": _count(max_svg_bytes, "max_svg_bytes"),
        "max_header_bytes": _count(max_header_bytes, "max_header_bytes"),
        "max_entries": _count(max_entries, "max_entries"),
        "max_depth": _count(max_depth, "max_depth"),
        "max_page_bytes": _count(max_page_bytes, "max_page_bytes"),
    })))


# Every public function and method reports a wrong argument as an InputError naming it; the
# functions also take Law/Model objects for law and model files, record their options as
# provenance and (the long ones) take progress= (_calls).
for _name in __all__:
    _obj = globals()[_name]
    if inspect.isfunction(_obj):
        globals()[_name] = _calls.public(_argument_errors(_obj))
for _cls in (Model, Law):
    for _name, _obj in list(vars(_cls).items()):
        if inspect.isfunction(_obj) and not _name.startswith("_"):
            setattr(_cls, _name, _argument_errors(_obj))
        elif isinstance(_obj, staticmethod):
            setattr(_cls, _name, staticmethod(_argument_errors(_obj.__func__)))
del _name, _obj, _cls
