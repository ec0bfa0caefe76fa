# SPDX-License-Identifier: GPL-3.0-or-later
"""The result types of translucent's functions: objects with attributes and a readable repr.

Every result is also a mapping with the keys of the command line's JSON (``r["key"]``,
``r.keys()``, ``"key" in r``, ``dict(r)``), as the functions returned plain dicts before; that
access is kept for compatibility and will be removed in a later release: use the attributes.
"""
from __future__ import annotations

import collections.abc
import keyword
from typing import Any, Dict, Iterator, List, Mapping, Optional

import numpy as np

__all__ = [
    "Result", "ChannelProperties", "ProfileEnergy", "SlabResult", "SphereIntegration",
    "SphereTrace", "MeshTrace", "Frame", "RenderPass", "TechniqueParameter", "GlInfo",
    "CompareReport",
]


def _short(value: Any) -> str:
    """A value for a repr: arrays by shape and type, long lists and dicts abbreviated."""
    if isinstance(value, np.ndarray):
        if value.size <= 3:
            return np.array2string(value, separator=", ")
        return f"<array {value.dtype} {value.shape}>"
    if isinstance(value, Result):
        return f"<{type(value).__name__}>"
    if isinstance(value, dict):
        return "{" + ", ".join(sorted(map(str, value))) + "}" if len(value) <= 4 \
            else f"<dict of {len(value)}>"
    if isinstance(value, list) and len(value) > 3:
        return f"<list of {len(value)}>"
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _equal(a: Any, b: Any) -> bool:
    """==, with NumPy arrays compared as a whole (array_equal), also inside dicts and lists."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return bool(np.array_equal(a, b))
    if isinstance(a, collections.abc.Mapping) and isinstance(b, collections.abc.Mapping):
        return a.keys() == b.keys() and all(_equal(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return type(a) is type(b) and len(a) == len(b) and all(map(_equal, a, b))
    return bool(a == b)


class Result(collections.abc.MutableMapping):
    """A result of the library: its fields are attributes (``r.diffuse_reflectance``).

    Also a mapping with the same keys (``r["diffuse_reflectance"]``, ``r.keys()``, ``in``),
    as the plain dicts that the functions returned before; prefer the attributes: the mapping
    access will be removed in a later release. ``to_dict()`` gives a plain dict.
    """

    __slots__ = ("_fields",)

    def __init__(self, fields: Optional[Mapping[str, Any]] = None, **more: Any) -> None:
        object.__setattr__(self, "_fields", dict(fields or {}, **more))

    # Attributes.
    def __getattr__(self, name: str) -> Any:
        fields = object.__getattribute__(self, "_fields")
        if name in fields:
            return fields[name]
        # A key that is a Python keyword is also reachable with a trailing underscore.
        if name.endswith("_") and keyword.iskeyword(name[:-1]) and name[:-1] in fields:
            return fields[name[:-1]]
        raise AttributeError(f"{type(self).__name__} has no field {name!r} "
                             f"(fields: {', '.join(fields)})")

    def __setattr__(self, name: str, value: Any) -> None:
        self._fields[name] = value

    def __dir__(self) -> List[str]:
        return sorted(set(super().__dir__()) | {k for k in self._fields if k.isidentifier()})

    # The mapping (compatibility with the dicts of earlier releases).
    def __getitem__(self, key: str) -> Any:
        return self._fields[key]

    def __setitem__(self, key: str, value: Any) -> None:
        self._fields[key] = value

    def __delitem__(self, key: str) -> None:
        del self._fields[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._fields)

    def __len__(self) -> int:
        return len(self._fields)

    def __eq__(self, other: object) -> bool:
        if isinstance(other, collections.abc.Mapping):
            return _equal(self._fields, dict(other.items()))
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]

    def to_dict(self) -> Dict[str, Any]:
        """The fields as a plain dict (nested results stay as they are)."""
        return dict(self._fields)

    def __repr__(self) -> str:
        inner = ", ".join(f"{k}={_short(v)}" for k, v in self._fields.items())
        return f"{type(self).__name__}({inner})"

    def _repr_pretty_(self, p: Any, cycle: bool) -> None:  # IPython
        p.text(repr(self))

    def __getstate__(self) -> Dict[str, Any]:
        return self._fields

    def __setstate__(self, state: Dict[str, Any]) -> None:
        object.__setattr__(self, "_fields", dict(state))


class ChannelProperties(Result):
    """One channel of a Medium (Medium.channel(c)), coefficients per scene unit (σ · scale)."""
    sigma_a: float
    sigma_s: float
    g: float
    eta: float
    sigma_tr: float
    albedo: float
    reduced_albedo: float
    diffuse_mean_free_path: float
    reduced_mean_free_path: float


class ProfileEnergy(Result):
    """BssrdfModel.energy(): total diffuse reflectance and the radius holding a fraction of it."""
    Rd: np.ndarray
    radius: np.ndarray


class SlabResult(Result):
    """translucent.pathtrace_slab(): the keys of `translucent pathtrace slab --json`."""
    specular_reflectance: float
    diffuse_reflectance: float
    transmittance: float
    diffuse_transmittance: float
    unscattered_transmittance: float
    absorbed: float
    photons: int
    seconds: float
    photons_per_second: float
    threads: int
    seed: int
    partial: bool
    device: str
    scattering_orders: Dict[str, Any]


class SphereIntegration(Result):
    """translucent.integrate_sphere(): images of the model integrated over the lit sphere."""
    exitance: np.ndarray
    exitance_stderr: np.ndarray
    radiance: np.ndarray
    radiance_stderr: np.ndarray
    model: str
    sampling: str
    defensive: float
    samples_per_pixel: int
    seconds: float
    threads: int
    partial: bool
    seed: int
    medium: Any


class SphereTrace(Result):
    """translucent.pathtrace_sphere(): the lit sphere's photon-traced images and statistics."""
    exitance: np.ndarray
    exitance_stderr: np.ndarray
    radiance: np.ndarray
    radiance_stderr: np.ndarray
    cone_radiance: np.ndarray
    cone_radiance_stderr: np.ndarray
    photons_per_channel: int
    passes: int
    seconds: float
    photons_per_second: float
    threads: int
    cone_angle: float
    device: str
    flux_per_channel: List[Dict[str, Any]]
    partial: bool
    seed: int
    medium: Any


class MeshTrace(Result):
    """translucent.pathtrace_mesh(): images and the keys of `pathtrace mesh --json`."""
    exitance: np.ndarray
    exitance_stderr: np.ndarray
    radiance: np.ndarray
    radiance_stderr: np.ndarray
    cone_radiance: np.ndarray
    cone_radiance_stderr: np.ndarray
    scene: Dict[str, Any]
    triangles: int
    photons_per_channel: int
    passes: int
    seconds: float
    photons_per_second: float
    scattering_events: int
    photons_in_several_pixels: int
    median_relative_stderr: List[float]
    majorant_violations: int
    threads: int
    device: str
    flux_per_channel: List[Dict[str, Any]]
    partial: bool
    seed: int
    reference_key: str


class RenderPass(Result):
    """One GPU pass of a rendered frame: name, time [ms] and nesting depth."""
    name: str
    ms: float
    depth: int


class Frame(Result):
    """translucent.render() and Renderer.render(): one frame of a technique."""
    image: np.ndarray
    layers: Dict[str, np.ndarray]
    passes: List[RenderPass]
    total_ms: float
    converged: bool
    notes: List[str]
    technique: str


class TechniqueParameter(Result):
    """A technique's parameter (translucent.technique_parameters())."""
    name: str
    type: str
    default: Any
    min: float
    max: float
    choices: List[str]
    unit: str
    help: str
    sweep: List[float]


class GlInfo(Result):
    """translucent.gl_info(): the module's OpenGL context."""
    renderer: str
    version: str
    vendor: str
    platform: str
    software: bool


class CompareReport(Result):
    """translucent.compare(): the report (report.json's keys)."""
    metrics: List[Dict[str, Any]]
    techniques: List[Dict[str, Any]]
    references: List[Dict[str, Any]]
    sweep: List[Dict[str, Any]]
    notes: List[str]
    partial: bool
    scene: Dict[str, Any]
    settings: Dict[str, Any]
