"""Shared fixtures: the repository root and the built `mrbrake` CLI, the reference the Python
package must agree with (the same inputs give the same JSON)."""

import json
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]


def cli_path():
    """The CLI binary: $MRBRAKE_CLI, else the release build in the workspace's target folder."""
    explicit = os.environ.get("MRBRAKE_CLI")
    if explicit:
        return pathlib.Path(explicit)
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    return target / "release" / "mrbrake"


class Cli:
    """Runs the CLI; `json(...)` parses `--json` output, `fail(...)` returns (exit code, message)."""

    def __init__(self, path):
        self.path = path

    def run(self, *args, cwd=None):
        return subprocess.run([str(self.path), *map(str, args)], capture_output=True, text=True,
                              cwd=cwd or ROOT, check=False)

    def json(self, *args, cwd=None):
        done = self.run(*args, "--json", cwd=cwd)
        assert done.returncode == 0, done.stderr
        return json.loads(done.stdout)

    def fail(self, *args, cwd=None):
        done = self.run(*args, cwd=cwd)
        assert done.returncode != 0, done.stdout
        # The message runs from `error: ` to the end (invalid fields take one line each).
        start = done.stderr.find("error: ")
        assert start >= 0, done.stderr
        return done.returncode, done.stderr[start + len("error: "):].rstrip("\n")


@pytest.fixture(scope="session")
def cli():
    path = cli_path()
    if not path.is_file():
        pytest.fail(f"the mrbrake CLI is not built at {path}: run `cargo build --release -p "
                    "mrbrake-cli` or set MRBRAKE_CLI")
    return Cli(path)


@pytest.fixture(scope="session")
def root():
    return ROOT
