"""Shared by the tests: the repository root and the `signorini` command
(`cargo xtask test` builds it and passes its path in SIGNORINI_BIN; run
alone, pytest looks in target/release and the comparisons skip if it is
not built)."""

import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXE = pathlib.Path(os.environ.get("SIGNORINI_BIN", ROOT / "target" / "release" / "signorini"))
XTASK = pathlib.Path(os.environ.get("SIGNORINI_XTASK", ROOT / "target" / "release" / "xtask"))


@pytest.fixture
def exe():
    if not EXE.exists():
        pytest.skip(f"the signorini command is not built ({EXE}): cargo build --release")
    return EXE


@pytest.fixture
def xtask():
    if not XTASK.exists():
        pytest.skip(f"the xtask command is not built ({XTASK}): cargo build --release -p xtask")
    return XTASK
