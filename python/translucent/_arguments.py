# SPDX-License-Identifier: GPL-3.0-or-later
"""Arguments the compiled module could not convert, named.

When no signature of a compiled function accepts the arguments of a call, pybind11 raises
"f(): incompatible function arguments" followed by every signature: the argument at fault is
left to the reader (an integer beyond 64 bits, a NUL character in a file name, a lone surrogate
in a text). wrap() puts a thin Python function around each compiled function and method that
catches that TypeError, finds the argument that cannot be converted from the signatures pybind11
lists, and raises TypeError (wrong type) or ValueError (a value its C++ type cannot hold) naming
it as the other checks of the module do ("threads=1099511627776: expected an integer in
[-2147483648, 2147483647]"). Calls that succeed pay one Python call more.
"""
import functools
import operator
import os
import re

_INT32 = (-2**31, 2**31 - 1)
_INT64 = (-2**63, 2**64 - 1)  # from the least int64 to the greatest uint64
_MARKER = "incompatible function arguments"
_SIGNATURE = re.compile(r"^\s*\d+\. (\(.*\))(?: -> .*)?$")


def _split_top(text):
    """`text` split at the commas outside brackets and quotes."""
    parts, depth, quote, start = [], 0, None, 0
    for i, ch in enumerate(text):
        if quote:
            if ch == quote and text[i - 1] != "\\":
                quote = None
        elif ch in "'\"":
            quote = ch
        elif ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append(text[start:i])
            start = i + 1
    parts.append(text[start:])
    return [p.strip() for p in parts if p.strip()]


def _parameters(signature):
    """[(name, annotation, keyword_only)] of a pybind11 signature "(a: int, *, b: str = 'x')"."""
    out, keyword_only = [], False
    for part in _split_top(signature[1:-1]):
        if part == "*":
            keyword_only = True
            continue
        if part.startswith("*"):  # *args, **kwargs: anything goes
            continue
        name, _, rest = part.partition(":")
        annotation = rest.split(" = ", 1)[0].strip()
        out.append((name.strip(), annotation, keyword_only))
    return out


def _bind(parameters, args, kwargs):
    """[(name, annotation, value)] of the arguments given, or None where they do not fit."""
    positional = [p for p in parameters if not p[2]]
    if len(args) > len(positional):
        return None
    bound = [(p[0], p[1], v) for p, v in zip(positional, args)]
    names = {p[0]: p for p in parameters}
    for key, value in kwargs.items():
        if key not in names:
            return None
        bound.append((key, names[key][1], value))
    return bound


def _show(value):
    """repr(value) for a message: at most 200 characters, long integers abbreviated, and the
    type's name where repr() itself fails (nesting past the recursion limit, a raising
    __repr__)."""
    try:
        if isinstance(value, int) and not isinstance(value, bool) and abs(value) >= 10**30:
            digits = str(abs(value))
            text = f"{'-' if value < 0 else ''}{digits[:8]}... ({len(digits)} digits)"
        else:
            text = repr(value)
    except Exception:  # noqa: BLE001 - any failure of a user's __repr__
        text = f"<{type(value).__name__} object>"
    return text if len(text) <= 200 else text[:197] + "..."


def _definite(name, annotation, value):
    """(exception type, message) when `value` cannot be converted to `annotation`'s C++ type on
    any reading of it; None when it can, or when it depends on the C++ integer type (_range)."""
    a = annotation
    m = re.fullmatch(r"Optional\[(.*)\]", a)
    if m:
        return None if value is None else _definite(name, m.group(1), value)
    m = re.fullmatch(r"Union\[(.*)\]", a)
    if m:
        problems = [_definite(name, o, value) for o in _split_top(m.group(1))]
        return None if any(p is None for p in problems) else problems[0]
    m = re.fullmatch(r"(?:List|Sequence|list)\[(.*)\]", a)
    if m:
        if isinstance(value, (str, bytes)) or not hasattr(value, "__iter__"):
            return TypeError, f"{name}={_show(value)}: expected a list"
        for i, item in enumerate(value):
            problem = _definite(f"{name}[{i}]", m.group(1), item)
            if problem:
                return problem
        return None
    if a == "int":
        try:
            if isinstance(value, float):
                raise TypeError
            v = operator.index(value)
        except Exception:  # noqa: BLE001 - no __index__, or one that raises
            return TypeError, f"{name}={_show(value)}: expected an integer"
        if not _INT64[0] <= v <= _INT64[1]:
            return ValueError, f"{name}={_show(v)}: expected an integer of at most 64 bits"
        return None
    if a == "float":
        # As pybind11's caster: __float__ or __index__ (float() would also parse text).
        try:
            if isinstance(value, (str, bytes, bytearray)):
                raise TypeError
            float(value)
        except OverflowError:
            return ValueError, f"{name}={_show(value)}: beyond the range of a double (±1.8e308)"
        except Exception:  # noqa: BLE001 - an array of several values, a raising __float__
            return TypeError, f"{name}={_show(value)}: expected a number"
        return None
    if a == "str":
        if not isinstance(value, (str, bytes)):
            return TypeError, f"{name}={_show(value)}: expected a str"
        if isinstance(value, str):
            try:
                value.encode("utf-8")
            except UnicodeEncodeError as e:
                return ValueError, (f"{name}={_show(value)}: not valid Unicode text (a lone "
                                    f"surrogate at index {e.start})")
        return None
    if a == "bool":
        if value is None or isinstance(value, bool) or type(value).__name__ == "bool_" or \
                hasattr(type(value), "__bool__"):
            return None
        return TypeError, f"{name}={_show(value)}: expected True or False"
    if a in ("os.PathLike", "pathlib.Path") or a.startswith("os.PathLike"):
        if not isinstance(value, (str, bytes, os.PathLike)):
            return TypeError, f"{name}={_show(value)}: expected a file name (str or os.PathLike)"
        try:
            path = os.fspath(value)
        except Exception as e:  # noqa: BLE001 - a __fspath__ that raises or returns another type
            return TypeError, (f"{name}={_show(value)}: expected a file name (str or "
                               f"os.PathLike; its __fspath__ raised {type(e).__name__})")
        if ("\0" if isinstance(path, str) else b"\0") in path:
            return ValueError, f"{name}={_show(value)}: a file name cannot hold a NUL character"
        try:
            os.fsencode(path)
        except UnicodeEncodeError as e:
            return ValueError, (f"{name}={_show(value)}: not a valid file name (a lone surrogate "
                                f"at index {e.start})")
        return None
    m = re.fullmatch(r"translucent\._translucent\.(\w+)", a)
    if m:  # one of the module's classes (none converts implicitly from another type)
        from . import _translucent
        cls = getattr(_translucent, m.group(1), None)
        if isinstance(cls, type) and not isinstance(value, cls):
            return TypeError, f"{name}={_show(value)}: expected a translucent.{m.group(1)}"
        return None
    if a == "dict":
        return None if isinstance(value, dict) else (
            TypeError, f"{name}={_show(value)}: expected a dict")
    return None  # object: the function checks it itself


def _range(name, annotation, value):
    """For integers that fit 64 bits but not every C++ integer type: a negative value for an
    unsigned argument, or one beyond 32 bits for an `int` argument (the module's integer
    arguments are int, int64 or uint64, so a failing value names its type)."""
    a = re.sub(r"^Optional\[(.*)\]$", r"\1", annotation)
    if a != "int" or isinstance(value, float) or not hasattr(type(value), "__index__"):
        return None
    v = operator.index(value)
    if v < 0:
        return ValueError, f"{name}={_show(v)}: expected an integer >= 0"
    if v > _INT32[1]:
        return ValueError, f"{name}={_show(v)}: expected an integer in [{_INT32[0]}, {_INT32[1]}]"
    return None


def diagnose(message, args, kwargs, names=None):
    """(exception type, message) for a failed call's pybind11 `message`, or None. `names`
    replaces the signature's parameter names (a property setter's arg0, arg1)."""
    signatures = [m.group(1) for m in map(_SIGNATURE.match, message.splitlines()) if m]
    candidates = []
    for signature in signatures:
        parameters = _parameters(signature)
        if names:
            parameters = [(n, a, k) for n, (_, a, k) in zip(names, parameters)]
        bound = _bind(parameters, args, kwargs)
        if bound is not None:
            candidates.append(bound)
    if len(candidates) != 1:  # ambiguous overloads, or the call fits none by name or count
        return None
    for check in (_definite, _range):
        for name, annotation, value in candidates[0]:
            problem = check(name, annotation, value)
            if problem:
                return problem
    return None


def _wrapped(function, names=None):
    @functools.wraps(function)
    def call(*args, **kwargs):
        try:
            return function(*args, **kwargs)
        except TypeError as e:
            text = str(e)
            if _MARKER not in text:
                raise
            try:
                problem = diagnose(text, args, kwargs, names)
            except Exception:  # noqa: BLE001 - a user's object that fails __float__, __index__, ...
                problem = None  # pybind11's message stands
            if problem is None:
                raise
            raise problem[0](problem[1]) from None
    return call


def wrap(module_namespace, names, classes):
    """Wraps the compiled functions `names` of `module_namespace` (a dict: the package's
    globals) and every method, static method and property setter of `classes`."""
    for name in names:
        module_namespace[name] = _wrapped(module_namespace[name])
    for cls in classes:
        for attr, member in list(vars(cls).items()):
            if attr.startswith("__") and attr != "__init__":
                continue
            if isinstance(member, staticmethod):
                setattr(cls, attr, staticmethod(_wrapped(member.__func__)))
            elif isinstance(member, property):
                if member.fset is not None:
                    setattr(cls, attr, property(member.fget, _wrapped(member.fset, ["self", attr]),
                                                member.fdel, member.__doc__))
            elif callable(member) and type(member).__name__ in ("instancemethod",
                                                                 "builtin_function_or_method",
                                                                 "wrapper_descriptor"):
                if attr == "__init__" and type(member).__name__ == "wrapper_descriptor":
                    continue  # object.__init__ of a class without a constructor
                setattr(cls, attr, _wrapped(member))
