# SPDX-License-Identifier: GPL-3.0-or-later
"""Translucent: rendering, comparing and validating translucent materials.

Media and presets (Medium, presets(), preset()), BSSRDF models by name (model(), model_names(),
profile(); .bssrdf files: BssrdfModel), the (Rd, ℓd) inversion (invert()), the reference path
tracers (pathtrace_slab(), pathtrace_sphere(), pathtrace_mesh()), the model integrated over the
lit sphere (integrate_sphere()), scenes (Scene), the real-time techniques on a headless GL context
(render(), Renderer, techniques(), technique_parameters()) and compare().

Lengths are in scene units (mm unless a medium's scale says otherwise), coefficients in 1/mm,
images (height, width, 3) float32 arrays, rows from the top. Results are typed objects
(translucent.SlabResult, Frame, ...) whose fields are attributes; they are also mappings with
the keys of the command line's JSON files. A bad argument raises ValueError (or TypeError for a
wrong type) naming the argument; other failures RuntimeError. Long calls release the GIL;
Ctrl-C stops the path tracers and compare with KeyboardInterrupt, whose `partial_result`
attribute holds what was computed so far. share_directory() is the folder of the shaders and
data the module uses.
"""
from ._results import (ChannelProperties, CompareReport, Frame, GlInfo, MeshTrace,
                       ProfileEnergy, RenderPass, Result, SlabResult, SphereIntegration,
                       SphereTrace, TechniqueParameter)
from ._translucent import (BssrdfModel, Medium, Model, Preset, Profiles, Renderer, Scene,
                           __version__, compare, fdr, gl_info, integrate_sphere, invert, model,
                           model_names, pathtrace_mesh, pathtrace_slab, pathtrace_sphere, preset,
                           presets, profile, render, share_directory, technique_parameters,
                           techniques)

__all__ = [
    # media, presets and models
    "Medium", "Preset", "presets", "preset", "fdr", "invert",
    "Model", "model", "model_names", "Profiles", "profile", "BssrdfModel",
    # references
    "pathtrace_slab", "pathtrace_sphere", "pathtrace_mesh", "integrate_sphere",
    # scenes, techniques, compare
    "Scene", "Renderer", "render", "techniques", "technique_parameters", "gl_info", "compare",
    # results
    "Result", "ChannelProperties", "ProfileEnergy", "SlabResult", "SphereIntegration",
    "SphereTrace", "MeshTrace", "Frame", "RenderPass", "TechniqueParameter", "GlInfo",
    "CompareReport",
    # the package
    "share_directory", "__version__",
]

# The extension's classes present themselves as translucent.X (repr, help, pickling).
for _cls in (BssrdfModel, Medium, Model, Preset, Profiles, Renderer, Scene):
    try:
        _cls.__module__ = __name__
    except (AttributeError, TypeError):  # pragma: no cover - older pybind11
        pass
del _cls

# An argument that no signature accepts raises TypeError or ValueError naming it (not pybind11's
# list of signatures): _arguments.py.
from . import _arguments  # noqa: E402

_arguments.wrap(globals(),
                ["compare", "fdr", "gl_info", "integrate_sphere", "invert", "model", "model_names",
                 "pathtrace_mesh", "pathtrace_slab", "pathtrace_sphere", "preset", "presets",
                 "profile", "render", "share_directory", "technique_parameters", "techniques"],
                [BssrdfModel, Medium, Model, Preset, Profiles, Renderer, Scene])
del _arguments
