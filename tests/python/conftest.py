# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared fixtures of the Python binding tests (run by ctest, label `python`).

ctest sets PYTHONPATH to the build tree's module folder, TRANSLUCENT_CLI to the `translucent`
program and TRANSLUCENT_SOURCE_DIR to the source tree: the tests compare every binding with the
command line's output files.
"""
import json
import os
import pathlib
import re
import subprocess

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("TRANSLUCENT_SOURCE_DIR",
                                         pathlib.Path(__file__).resolve().parents[2]))


@pytest.fixture(scope="session")
def source_dir():
    return SOURCE_DIR


@pytest.fixture(scope="session")
def cli():
    """Runs `translucent ARGS...`; returns the completed process (check=True unless told)."""
    program = os.environ.get("TRANSLUCENT_CLI")
    assert program and os.access(program, os.X_OK), \
        "TRANSLUCENT_CLI must name the translucent program (ctest sets it)"

    def run(*args, check=True):
        p = subprocess.run([program, *map(str, args)], capture_output=True, text=True,
                           timeout=600)
        if check and p.returncode != 0:
            raise AssertionError(f"translucent {' '.join(map(str, args))} failed:\n{p.stderr}")
        return p
    return run


@pytest.fixture(scope="session")
def cli_error(cli):
    """The message of a failing CLI call (its stderr line without the 'translucent: error: ')."""
    def run(*args):
        p = cli(*args, check=False)
        assert p.returncode != 0, f"expected translucent {args} to fail"
        line = p.stderr.strip().splitlines()[-1]
        prefix = "translucent: error: "
        assert line.startswith(prefix), line
        return line[len(prefix):]
    return run


def python_message(message):
    """A CLI error message as the module words it: option names become the Python arguments'
    names ("--sigma-a" -> "sigma_a") and an option with its quoted value an assignment
    ("--channel 'x'" -> "channel='x'")."""
    def name(m):
        return m.group(1).replace("-", "_") + ("=" if m.group(2) else "")
    return re.sub(r"(?<![\w-])--([a-z][a-z0-9-]*[a-z0-9]|[a-z])( (?='))?", name, message)


@pytest.fixture(scope="session")
def as_python():
    """python_message as a fixture."""
    return python_message


def read_json(path):
    with open(path) as f:
        return json.load(f)
