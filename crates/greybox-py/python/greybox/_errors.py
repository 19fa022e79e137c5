"""greybox's exceptions: one hierarchy under :class:`GreyboxError`.

The native module picks the class by the kind of the Rust error (``src/errors.rs``); the
Python layer raises :class:`InputError` for a wrong argument. Each also derives from the
built-in exception a Python user would catch for that kind (``ValueError``,
``FileNotFoundError``), so ``except ValueError`` keeps working.
"""


class GreyboxError(Exception):
    """Any error of greybox, with the command line's message (naming the file, line or
    field at fault)."""


class InputError(GreyboxError, ValueError):
    """Bad input: a wrong argument, an invalid file, a value out of range."""


class SettingsError(InputError):
    """Settings (a stage's options, a JSON or TOML settings text) that the library refuses."""


class MissingFileError(InputError, FileNotFoundError):
    """A file or directory the call needs is not there."""


class UnusualValueWarning(UserWarning):
    """A value outside its usual range that greybox accepted (the physics table's flags:
    a density of 7.85 kg/m³, μ = 1.5, 20 K): the message names the setting, the number, the
    ranges and the likely unit mistake. The command line prints the same text as
    ``warning: …``."""
