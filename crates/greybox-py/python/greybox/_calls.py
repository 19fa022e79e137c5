"""What every public function does around its work, in one place: Law and Model objects
accepted where a law or model file is, the call's function name and options recorded as the
provenance command of what it writes, ``progress=`` for the long calls (:mod:`._progress`),
and a wrong argument reported as :class:`InputError`.

The native module reads the progress callback and the command from the calling thread
(``_native.swap_call``), so the public functions' bodies stay as they were.
"""

from __future__ import annotations

import contextlib
import functools
import inspect
import json
import os
import tempfile
from typing import Any, Callable

import numpy as np

from . import _native, _progress
from ._errors import InputError


#: Arguments that name a law file (a Law or Model object is written to a temporary file).
LAW_ARGS = frozenset({"law"})


def _jsonable(v: Any) -> Any:
    """An argument as JSON for the provenance record (a large array by its shape only)."""
    if v is None or isinstance(v, (bool, int, float, str)):
        return v
    if isinstance(v, os.PathLike):
        return os.fspath(v)
    if isinstance(v, np.ndarray):
        return v.tolist() if v.size <= 100 else f"<array of shape {v.shape}>"
    if isinstance(v, dict):
        return {str(k): _jsonable(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_jsonable(x) for x in v] if len(v) <= 100 else f"<{len(v)} items>"
    return repr(v)


def command(name: str, bound: inspect.BoundArguments) -> list:
    """The provenance command of a call: ``["greybox.<name>", JSON of its arguments]`` (every
    argument by name, defaults included)."""
    return [f"greybox.{name}", json.dumps({k: _jsonable(v) for k, v in bound.arguments.items()})]


def _as_files(f: Callable, bound: inspect.BoundArguments, stack: contextlib.ExitStack) -> None:
    """Replace Law/Model objects given for a law or model file by files written into a
    temporary folder that ``stack`` removes (for ``grey_box_law``'s ``model``: beside
    ``out``, since the law file refers to it)."""
    from . import Law, Model

    for name, v in bound.arguments.items():
        if name in LAW_ARGS and isinstance(v, (Law, Model)):
            bound.arguments[name] = v._write_into(stack.enter_context(tempfile.TemporaryDirectory()))
        elif name == "model" and f.__name__ == "grey_box_law" and isinstance(v, Model):
            out = bound.arguments.get("out")
            out = os.fspath(out) if out is not None else library_default("law", "out")
            model_file = os.path.splitext(os.path.basename(out))[0] + ".model.json"
            v.save(os.path.join(os.path.dirname(os.path.abspath(out)), model_file))
            bound.arguments[name] = model_file  # relative: resolved against the law file's folder


def library_default(stage: str, key: str) -> Any:
    """The library's default of setting ``key`` of ``stage`` (where Python needs the value a
    ``None`` stands for, e.g. the law file to read back)."""
    return json.loads(_native.settings_defaults(stage))[key]


def public(f: Callable) -> Callable:
    """Wrap the public function ``f`` (see the module's doc)."""
    sig = inspect.signature(f)
    # the long calls (those that may run for minutes) declare a keyword-only `progress`
    # (typed, so that type checkers see it); the wrapper takes it, the body never sees it
    long = "progress" in sig.parameters

    @functools.wraps(f)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        progress = kwargs.pop("progress", None) if long else None
        try:
            bound = sig.bind(*args, **kwargs)
        except TypeError as e:
            raise InputError(f"{f.__name__}: {e}") from None
        bound.apply_defaults()
        bound.arguments.pop("progress", None)  # the call's reporting, not one of its settings
        cmd = command(f.__name__, bound)
        with contextlib.ExitStack() as stack:
            callback = stack.enter_context(_progress.reporter(progress, f.__name__))
            _as_files(f, bound, stack)
            previous = _native.swap_call(callback, cmd)
            try:
                return f(*bound.args, **bound.kwargs)
            finally:
                _native.swap_call(*previous)

    return wrapper
