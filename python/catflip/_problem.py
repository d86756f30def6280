"""Loading a problem: a path, a TOML string or a dict, with ``--set``-style overrides.

A dict is written as TOML text and loaded as the text would be, and an override ``{key: value}``
becomes the CLI's ``key=value`` with the value in TOML syntax, so the library's one parser and
one validation see every problem, whatever it came as: the errors are the CLI's, word for word.
"""

from __future__ import annotations

import math
import os
import sys
import warnings
from typing import Any, Mapping, Sequence, Union

from . import _catflip
from ._catflip import Problem

Overrides = Union[Mapping[str, Any], Sequence[str], None]
Source = Union[str, "os.PathLike[str]", Mapping[str, Any]]


class CatflipWarning(UserWarning):
    """What the CLI prints as ``warning: …``: careless input that is not an error."""


#: The package's own folder: a warning is attributed to the first caller outside it.
_PACKAGE_DIR = os.path.dirname(os.path.abspath(__file__))


def _caller_level() -> int:
    """The ``stacklevel`` of the first frame outside the package, as seen from :func:`_warn`'s
    call to :func:`warnings.warn` (1 is :func:`_warn` itself), so that a warning points at the
    user's line whichever of the package's functions raised it."""
    frame = sys._getframe(1)
    level = 1
    while frame is not None and os.path.dirname(os.path.abspath(frame.f_code.co_filename)) == _PACKAGE_DIR:
        frame = frame.f_back
        level += 1
    return level


def _warn(messages: Sequence[str]) -> None:
    for m in messages:
        warnings.warn(m, CatflipWarning, stacklevel=_caller_level())


def toml_value(value: Any) -> str:
    """``value`` in TOML syntax: booleans, integers, floats (``inf``, ``nan`` included), strings
    (quoted), lists and inline tables."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return _quote(value)
    if isinstance(value, Mapping):
        return "{" + ", ".join(f"{_key(k)} = {toml_value(v)}" for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)) or hasattr(value, "tolist"):
        items = value.tolist() if hasattr(value, "tolist") else value
        if not isinstance(items, list):
            return toml_value(items)
        return "[" + ", ".join(toml_value(v) for v in items) + "]"
    raise TypeError(f"{value!r} ({type(value).__name__}) has no TOML form")


def _quote(text: str) -> str:
    out = []
    for c in text:
        if c == '"' or c == "\\":
            out.append("\\" + c)
        elif ord(c) < 0x20 or ord(c) == 0x7F:
            out.append(f"\\u{ord(c):04x}")
        else:
            out.append(c)
    return '"' + "".join(out) + '"'


def _key(key: Any) -> str:
    k = str(key)
    bare = k and all(c.isascii() and (c.isalnum() or c in "-_") for c in k)
    return k if bare else _quote(k)


def dict_to_toml(d: Mapping[str, Any]) -> str:
    """A problem given as nested dicts, as the TOML text of the same file: plain keys first,
    then one ``[section]`` per nested dict, ``[[name]]`` per dict of a list of dicts; ``None``
    is an absent optional field (TOML has no null)."""
    lines: list[str] = []

    def table(prefix: str, t: Mapping[str, Any]) -> None:
        subs: list[tuple[str, Any]] = []
        for k, v in t.items():
            if v is None:
                continue  # an absent optional field, as TOML writes none
            if isinstance(v, Mapping):
                subs.append((k, v))
            elif isinstance(v, (list, tuple)) and v and all(isinstance(x, Mapping) for x in v):
                subs.append((k, list(v)))
            else:
                lines.append(f"{_key(k)} = {toml_value(v)}")
        for k, v in subs:
            name = f"{prefix}.{_key(k)}" if prefix else _key(k)
            if isinstance(v, list):
                for item in v:
                    lines.append(f"[[{name}]]")
                    table(name, item)
            else:
                lines.append(f"[{name}]")
                table(name, v)

    table("", d)
    return "\n".join(lines) + "\n"


def override_list(overrides: Overrides) -> list[str]:
    """Overrides as the CLI's ``key=value`` strings: a list of them as given, or a dict
    ``{key: value}`` with each value written in TOML syntax."""
    if overrides is None:
        return []
    if isinstance(overrides, str):
        return [overrides]
    if isinstance(overrides, Mapping):
        return [f"{k}={toml_value(v)}" for k, v in overrides.items()]
    return [str(o) for o in overrides]


def load(source: Source, overrides: Overrides = None) -> Problem:
    """Loads a problem: a problem file's path (``str`` or ``os.PathLike``) or a dict of its
    sections, then applies ``overrides`` (``{"manoeuvre.profile": "cycloidal"}`` or
    ``["manoeuvre.profile=cycloidal"]``, as ``--set``) and validates it.

    Raises :class:`CatflipError` with the CLI's message (unknown field, wrong type, value out of
    range, bad override, unreadable file); warns with :class:`CatflipWarning` as the CLI does.
    """
    if isinstance(source, Mapping):
        return from_dict(source, overrides)
    problem = _catflip.load(os.fspath(source), override_list(overrides))
    _warn(problem.warnings())
    return problem


def loads(text: str, overrides: Overrides = None, origin: str = "<string>") -> Problem:
    """Loads a problem from TOML text (named ``origin`` in messages); see :func:`load`."""
    problem = _catflip.from_toml(text, origin, override_list(overrides))
    _warn(problem.warnings())
    return problem


def from_dict(d: Mapping[str, Any], overrides: Overrides = None, origin: str = "<dict>") -> Problem:
    """Loads a problem given as a dict of its sections (``{"cat": {"mass": 1.0}, ...}``, as
    :meth:`Problem.to_dict` returns); see :func:`load`."""
    return loads(dict_to_toml(d), overrides, origin)
