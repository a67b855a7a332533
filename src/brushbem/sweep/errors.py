"""The exceptions and the warning of sweeps, and how a problem line shows a value or an exception."""

from __future__ import annotations

from typing import Any

from brushbem.config import ConfigError

_MAX_SHOWN = 60


class SweepError(ConfigError):
    """A sweep that cannot run: every problem, one line each, in ``.problems``."""


class SweepFolderError(SweepError):
    """An output folder that holds another sweep, or whose ``sweep.json`` cannot be read."""


class SweepWarning(UserWarning):
    """Something in a sweep folder was repaired on reading (an unreadable summary rebuilt)."""


def _show(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= _MAX_SHOWN else text[: _MAX_SHOWN - 3] + "..."


def _brief(error: BaseException) -> str:
    """``Type: message`` of an exception, its first line, at most 160 characters."""
    try:
        lines = str(error).strip().splitlines()
    except Exception:  # noqa: BLE001 - an exception that cannot say what it is still has a type
        lines = []
    text = f"{type(error).__name__}: {lines[0] if lines else ''}".rstrip(": ")
    return text if len(text) <= 160 else text[:157] + "..."
