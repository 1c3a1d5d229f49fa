"""Paths shared by the tests: the repository root and the CLI binary built by cargo."""

import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(autouse=True)
def at_root(monkeypatch):
    """Scenes name their files relative to themselves; run from the root as the CLI does."""
    monkeypatch.chdir(ROOT)


@pytest.fixture
def cli():
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    exe = target / "release" / "towride"
    if not exe.exists():
        pytest.fail(f"{exe} missing: build it with cargo build --release")
    return str(exe)
