# SPDX-License-Identifier: GPL-3.0-or-later
# Sphinx configuration of the Translucent documentation (MyST Markdown, Furo theme).
# Built by scripts/build-docs, which first generates the CLI reference and the scene-format
# reference into build/docs/generated/ (included by reference/cli.md and
# reference/scene-format.md) and puts the built Python module on PYTHONPATH for autodoc.
project = "Translucent"
author = "The Translucent developers"
copyright = "The Translucent developers, GPL-3.0-or-later"
release = version = "0.1.0"

extensions = ["myst_parser", "sphinx.ext.autodoc"]
source_suffix = {".md": "markdown"}
master_doc = "index"
exclude_patterns = ["_build", "schema/*.json", "**/*.csv", "**/*.json"]
myst_enable_extensions = ["colon_fence", "dollarmath"]
myst_heading_anchors = 4
# Measured reports keep their own heading levels (they are also read as plain Markdown files).
suppress_warnings = ["myst.header"]

html_theme = "furo"
html_title = "Translucent"
html_static_path = []
html_show_sourcelink = False

# autodoc of the `translucent` module (pybind11): its docstrings are plain text written for
# help(), not reStructuredText, so each is shown as a literal block after its first line.
autodoc_member_order = "bysource"
autodoc_default_options = {"members": True, "undoc-members": True}


def _literal_docstring(app, what, name, obj, options, lines):
    if not lines:
        return
    text = [line for line in lines]
    while text and not text[-1].strip():
        text.pop()
    lines[:] = ["::", ""] + ["    " + line for line in text] + [""]


def setup(app):
    app.connect("autodoc-process-docstring", _literal_docstring)
