# SPDX-License-Identifier: GPL-3.0-or-later
"""Builds the package `translucent` (python/translucent/ and the extension _translucent) with
CMake, for pyproject.toml's setuptools backend.

TRANSLUCENT_CMAKE_BUILD_DIR: a configured CMake build tree (relative to this folder or absolute),
e.g. build/release: only its target translucent_python is built, and the module copied. Without
it, build/python is configured (once) as the release preset configures build/release, with the
interpreter that runs this build, and its target translucent_python built.
TRANSLUCENT_CMAKE_JOBS: parallel jobs (default: the CPU count).
The wheel holds the package, its type stubs and the shaders and data the module reads, in
translucent/share/translucent (found beside the module at run time).
"""
import os
import pathlib
import re
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext
from setuptools.command.build_py import build_py

ROOT = pathlib.Path(__file__).resolve().parent
SHARE = ("shaders", "data")  # the folders io::shareDirectory() looks for


def project_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    m = re.search(r"project\(\s*Translucent\s+VERSION\s+([0-9.]+)", text)
    if not m:
        raise RuntimeError("CMakeLists.txt: no project(Translucent VERSION x.y.z)")
    return m.group(1)


def run(cmd, **kwargs):
    print("+", " ".join(map(str, cmd)), flush=True)
    subprocess.run(list(map(str, cmd)), check=True, **kwargs)


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    """The extension from a CMake build tree's target translucent_python."""

    def build_extension(self, ext):
        given = os.environ.get("TRANSLUCENT_CMAKE_BUILD_DIR")
        if given:
            tree = pathlib.Path(given)
            tree = tree if tree.is_absolute() else ROOT / tree
            if not (tree / "CMakeCache.txt").is_file():
                raise RuntimeError(f"TRANSLUCENT_CMAKE_BUILD_DIR={given}: {tree} is not a "
                                   "configured CMake build tree (no CMakeCache.txt)")
        else:
            tree = ROOT / "build" / "python"
            if not (tree / "CMakeCache.txt").is_file():
                # The release preset's settings (CMakePresets.json), in another folder.
                run(["cmake", "--preset", "release", "-B", tree,
                     f"-DPython3_EXECUTABLE={sys.executable}", "-DTRANSLUCENT_PYTHON=ON"],
                    cwd=ROOT)
        jobs = os.environ.get("TRANSLUCENT_CMAKE_JOBS", str(os.cpu_count() or 1))
        run(["cmake", "--build", tree, "--target", "translucent_python", "-j", jobs])
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        built = tree / "python" / "translucent" / f"_translucent{suffix}"
        if not built.is_file():
            found = sorted((tree / "python" / "translucent").glob("_translucent*.so"))
            raise RuntimeError(
                f"{built} was not built: the tree {tree} builds for another interpreter "
                f"({', '.join(p.name for p in found) or 'no module'}; this is {sys.executable}, "
                f"{suffix}): give a tree configured with -DPython3_EXECUTABLE={sys.executable}")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)
        shutil.copymode(built, target)


class BuildPy(build_py):
    """The package's Python files, and the shaders and data under translucent/share/translucent."""

    def run(self):
        super().run()
        share = pathlib.Path(self.build_lib) / "translucent" / "share" / "translucent"
        for name in SHARE:
            dest = share / name
            if dest.exists():
                shutil.rmtree(dest)
            shutil.copytree(ROOT / name, dest)


# setuptools' intermediate folders inside build/ (git ignores it), not beside the sources.
(ROOT / "build" / "setuptools").mkdir(parents=True, exist_ok=True)

setup(
    version=project_version(),
    packages=["translucent"],
    package_dir={"": "python"},
    package_data={"translucent": ["py.typed", "*.pyi"]},
    ext_modules=[CMakeExtension("translucent._translucent")],
    cmdclass={"build_ext": CMakeBuild, "build_py": BuildPy},
    zip_safe=False,
    options={"build": {"build_base": "build/setuptools"},
             "egg_info": {"egg_base": "build/setuptools"}},
)
