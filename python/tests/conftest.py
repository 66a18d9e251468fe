"""Shared fixtures of hamel's Python tests."""

import os
import subprocess
from pathlib import Path

import pytest

REPOSITORY = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def repository() -> Path:
    return REPOSITORY


@pytest.fixture(scope="session")
def robot_csv(tmp_path_factory) -> Path:
    """The rows `cargo run --release --example mobile_robot` writes (the README's run): the
    file `$HAMEL_ROBOT_CSV` if set (CI makes it once), else made here with cargo."""
    given = os.environ.get("HAMEL_ROBOT_CSV")
    if given:
        return Path(given)
    out = tmp_path_factory.mktemp("robot") / "mobile_robot.csv"
    subprocess.run(["cargo", "run", "--release", "--quiet", "--example", "mobile_robot", "--",
                    "--out", str(out)], cwd=REPOSITORY, check=True, stdout=subprocess.DEVNULL)
    return out


@pytest.fixture(scope="session")
def readme_sleigh(repository) -> str:
    """The model of the README's first Rust block, the Chaplygin sleigh."""
    text = (repository / "README.md").read_text(encoding="utf-8")
    start = text.index("```rust\n") + len("```rust\n")
    return text[start:text.index("```", start)]
