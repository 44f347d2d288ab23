"""Strict, typed configuration base and YAML loading.

Every ``params.yaml`` section is a frozen pydantic model that rejects unknown
keys. Validation errors are turned into :class:`drillfatigue.errors.InputError`
with a dotted field path and the allowed range, so the CLI can print one line.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any, TypeVar

import yaml
from pydantic import BaseModel, ConfigDict, ValidationError

from drillfatigue.errors import InputError

M = TypeVar("M", bound=BaseModel)

_CONSTRAINT_WORDS = {
    "gt": ">",
    "ge": ">=",
    "lt": "<",
    "le": "<=",
    "multiple_of": "multiple of",
    "min_length": "length >=",
    "max_length": "length <=",
}


class StrictModel(BaseModel):
    """Frozen model that rejects unknown keys and validates defaults."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)


def _loc_to_path(prefix: str, loc: tuple[Any, ...]) -> str:
    parts: list[str] = [prefix] if prefix else []
    for item in loc:
        if isinstance(item, int):
            if parts:
                parts[-1] = f"{parts[-1]}[{item}]"
            else:
                parts.append(f"[{item}]")
        else:
            parts.append(str(item))
    return ".".join(parts) or "<root>"


def _allowed_from_ctx(err: Mapping[str, Any]) -> str | None:
    ctx = err.get("ctx") or {}
    bits = [f"{_CONSTRAINT_WORDS[k]} {ctx[k]}" for k in _CONSTRAINT_WORDS if k in ctx]
    if "expected" in ctx:
        bits.append(str(ctx["expected"]))
    if err.get("type") == "extra_forbidden":
        return "only the documented keys of this section"
    return ", ".join(bits) or None


def input_error_from_validation(exc: ValidationError, prefix: str = "") -> InputError:
    """Convert the first error of a pydantic ``ValidationError`` to an InputError."""
    return input_error_from_error(exc.errors(include_url=False)[0], prefix)


def input_error_from_error(err: Mapping[str, Any], prefix: str = "") -> InputError:
    """Convert one pydantic error entry (``ValidationError.errors()[i]``) to an InputError."""
    # Custom validators inside unions report the branch name in loc; drop
    # function-style tags such as 'function-after[...]'.
    loc = tuple(p for p in err["loc"] if not (isinstance(p, str) and "[" in p and "]" in p))
    path = _loc_to_path(prefix, loc)
    msg = str(err["msg"])
    if msg.startswith("Value error, "):
        msg = msg[len("Value error, "):]
    if err.get("type") == "extra_forbidden":
        msg = "unknown key"
    elif err.get("type") == "missing":
        msg = "required key is missing"
    inp = err.get("input")
    if err.get("type") not in ("missing", "extra_forbidden") and not isinstance(inp, dict | list):
        msg = f"{msg}, got {inp!r}"
    allowed = None if "(allowed:" in msg else _allowed_from_ctx(err)
    # A model-level validator names its own field path as "path: message".
    head, sep, tail = msg.partition(": ")
    if sep and " " not in head and (not loc or head.startswith(path.split(".")[-1])):
        path = f"{prefix}.{head}" if prefix else head
        msg = tail
    elif sep and " " not in head and isinstance(inp, dict):
        # a nested section's own validator names a field of that section
        path = f"{path}.{head}"
        msg = tail
    return InputError(path, msg, allowed)


def validate(model: type[M], data: Any, prefix: str = "") -> M:
    """Validate ``data`` against ``model``; raise InputError on failure."""
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        raise input_error_from_validation(exc, prefix) from None


def read_utf8(path: str | Path, allowed: str = "a UTF-8 encoded text file") -> str:
    """The text of ``path``; a file that is not UTF-8 raises InputError naming the byte."""
    p = Path(path)
    try:
        return p.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(str(p), f"not UTF-8 text (byte 0x{exc.object[exc.start]:02x} at "
                         f"offset {exc.start})", allowed) from None
    except OSError as exc:
        raise InputError(str(p), f"cannot be read ({exc.strerror or type(exc).__name__})",
                         "a readable file") from None


#: libyaml's parser where PyYAML was built with it (ten times faster on a case file;
#: the same constructors, so the same data).
_FAST_LOADER = getattr(yaml, "CSafeLoader", None)


def _load_yaml(text: str) -> Any:
    """``yaml.safe_load`` of ``text``, parsed by libyaml when available; a document it
    refuses is parsed again by the pure-Python parser, whose error message (line, column,
    problem) is the one every installation gives."""
    if _FAST_LOADER is not None:
        try:
            return yaml.load(text, Loader=_FAST_LOADER)  # noqa: S506 - a safe loader
        except yaml.YAMLError:
            pass
    return yaml.safe_load(text)


def read_yaml(path: str | Path) -> dict[str, Any]:
    """Read a YAML mapping; a missing, empty, non-UTF-8 file or bad syntax raises InputError."""
    p = Path(path)
    if not p.is_file():
        raise InputError(str(p), "file not found", "an existing YAML file")
    text = read_utf8(p, "a UTF-8 encoded YAML file")
    try:
        data = _load_yaml(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        problem = getattr(exc, "problem", None) or "invalid YAML"
        raise InputError(str(p), f"YAML syntax error{where}: {problem}", "valid YAML") from None
    if data is None:
        # an empty file is a mistake (a wrong path, a truncated copy), not a
        # request for the defaults: ``{}`` asks for those explicitly
        raise InputError(str(p), "the file is empty (no YAML content)",
                         "a YAML mapping of sections; write {} for all defaults")
    if not isinstance(data, dict):
        raise InputError(str(p), f"top level must be a mapping, got {type(data).__name__}",
                         "a YAML mapping of sections")
    return data
