# SPDX-License-Identifier: LGPL-2.1-or-later
"""Validating JSON fields of our file formats, with errors that name the field and value.

Each check returns the parsed value or raises `error(path, message, value)`, whose text
reads like "operations[2].d: expected a positive number, got -6".
"""

from __future__ import annotations

import json
import math
from typing import Any


class FieldError(ValueError):
    """A field of a file is malformed; the message names its path and the value."""


def error(path: str, msg: str, value: Any) -> FieldError:
    shown = (
        value
        if isinstance(value, str) and value.startswith("an integer of")
        else json.dumps(value, default=repr)
    )
    if len(shown) > 80:
        shown = shown[:77] + "..."
    return FieldError(f"{path}: {msg}, got {shown}")


def parse_json(text: str, source: str, fail: type[FieldError], what: str) -> Any:
    """JSON text as Python values, or `fail` prefixed with `source` when it is not JSON,
    is nested too deeply, or holds an integer past Python's digit limit (`what` names
    what the text should have been, as in "not a protocol")."""
    try:
        return json.loads(text)
    except json.JSONDecodeError as e:
        raise fail(f"{source}: not valid JSON: {e}") from None
    except RecursionError:
        raise fail(f"{source}: not a {what}: nested too deeply") from None
    except ValueError as e:  # an integer past Python's digit limit
        raise fail(f"{source}: not a {what}: {e}") from None


def obj(v: Any, path: str, required: set[str], optional: set[str] = frozenset()) -> dict:
    """A JSON object with exactly the required keys and perhaps some optional ones."""
    if not isinstance(v, dict):
        raise error(path, "expected an object", v)
    missing = sorted(required - v.keys())
    if missing:
        raise error(path, f"missing key '{missing[0]}'", v)
    extra = sorted(v.keys() - required - optional)
    if extra:
        raise error(
            f"{path}.{extra[0]}",
            f"unknown key (expected one of {sorted(required | optional)})",
            v[extra[0]],
        )
    return v


# The base box's sides (mm): from a micrometre to 100 m; OCCT fails outside.
MIN_BOX_MM, MAX_BOX_MM = 1e-3, 1e5


def number(v: Any, path: str, positive: bool = False, nonzero: bool = False) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise error(path, "expected a finite number", v)
    try:
        finite = math.isfinite(v)
    except OverflowError:  # an integer of hundreds of digits
        finite = False
    if not finite:
        raise error(
            path,
            "expected a finite number",
            v if isinstance(v, float) else f"an integer of {len(str(abs(v)))} digits",
        )
    if positive and v <= 0:
        raise error(path, "expected a positive number", v)
    if nonzero and v == 0:
        raise error(path, "expected a non-zero number", v)
    return float(v)


def vec(v: Any, path: str, n: int = 3) -> tuple[float, ...]:
    if not isinstance(v, list) or len(v) != n:
        raise error(path, f"expected a list of {n} numbers", v)
    return tuple(number(x, f"{path}[{i}]") for i, x in enumerate(v))


def points(v: Any, path: str, lo: int, hi: int, dim: int = 3) -> tuple:
    if not isinstance(v, list) or not lo <= len(v) <= hi:
        count = f"{lo}" if lo == hi else f"{lo} to {hi}"
        raise error(path, f"expected a list of {count} points", v)
    return tuple(vec(p, f"{path}[{i}]", dim) for i, p in enumerate(v))


def header(o: dict, fmt: str, version: int | tuple[int, ...]) -> None:
    """The format name, version (one, or those a build reads) and units (mm) every file
    of ours starts with."""
    versions = version if isinstance(version, tuple) else (version,)
    if o["format"] != fmt:
        raise error("format", f"expected '{fmt}'", o["format"])
    if isinstance(o["version"], bool) or o["version"] not in versions:
        names = [str(v) for v in versions]
        reads = " or ".join([", ".join(names[:-1]), names[-1]] if len(names) > 2 else names)
        raise error("version", f"unsupported version (this build reads {reads})", o["version"])
    if o["units"] != "mm":
        raise error("units", "expected 'mm'", o["units"])


def box_size(v: Any) -> tuple[float, float, float]:
    """The base box {"type": "box", "size": [lx, ly, lz]} (mm, all positive)."""
    base = obj(v, "base", {"type", "size"})
    if base["type"] != "box":
        raise error("base.type", "expected 'box'", base["type"])
    size = vec(base["size"], "base.size")
    for i, s in enumerate(size):
        number(s, f"base.size[{i}]", positive=True)
        if not MIN_BOX_MM <= s <= MAX_BOX_MM:
            raise error(
                f"base.size[{i}]", f"expected a side from {MIN_BOX_MM:g} to {MAX_BOX_MM:g} mm", s
            )
    return size
