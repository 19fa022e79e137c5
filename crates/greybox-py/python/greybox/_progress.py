"""Progress of long calls: silent unless asked.

A long call (``simulate_cut``, ``fit``, …) takes ``progress=``: ``None`` (the default)
reports nothing; ``True`` logs each stage's progress at INFO to the ``"greybox"`` logger
and, when ``tqdm`` is installed, draws a bar per stage; a callable is called as
``progress(stage, done, total)`` (``total`` None when unknown). The library throttles its
updates (about ten a second per stage) and the calls arrive on the calling thread with the
GIL held; an exception raised by the callable stops the call and propagates.
"""

from __future__ import annotations

import contextlib
import logging
from typing import Any, Callable, Iterator, Optional

from ._errors import InputError

logger = logging.getLogger("greybox")
# a library logs nowhere until the application configures logging
logger.addHandler(logging.NullHandler())

Callback = Callable[[str, int, Optional[int]], Any]


class _Reporter:
    """``progress=True``: INFO log records, and tqdm bars (one per stage) where installed."""

    def __init__(self, call: str):
        self.call = call
        self.bars: dict = {}
        try:
            import tqdm  # noqa: F401

            self.tqdm: Any = tqdm.tqdm
        except ImportError:
            self.tqdm = None

    def __call__(self, stage: str, done: int, total: Optional[int]) -> None:
        of = "" if total is None else f"/{total}"
        logger.info("%s: %s %d%s", self.call, stage, done, of)
        if self.tqdm is not None:
            bar = self.bars.get(stage)
            if bar is None:
                bar = self.bars[stage] = self.tqdm(total=total, desc=f"{self.call}: {stage}", leave=False)
            bar.update(done - bar.n)

    def close(self) -> None:
        for bar in self.bars.values():
            bar.close()


@contextlib.contextmanager
def reporter(progress: Any, call: str) -> Iterator[Optional[Callback]]:
    """The callback for ``progress=`` of the public function ``call`` (None: silent)."""
    if progress is None or progress is False:
        yield None
    elif progress is True:
        r = _Reporter(call)
        try:
            yield r
        finally:
            r.close()
    elif callable(progress):
        yield progress
    else:
        raise InputError(f"progress: expected None, True or a callable(stage, done, total), got {type(progress).__name__}")
