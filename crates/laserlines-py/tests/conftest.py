"""Shared fixtures: the repository's bundled data and the `laserlines` command to compare
with (LASERLINES_BIN, else target/release or target/debug, built with cargo when missing)."""

import json
import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[3]
EXCERPT = REPO / "data" / "urg04lx-exp1-excerpt.dat.gz"
FIXTURES = REPO / "crates" / "laserlines-foxglove" / "tests" / "fixtures"


def _find_cli():
    given = os.environ.get("LASERLINES_BIN")
    if given:
        return pathlib.Path(given)
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    for profile in ("release", "debug"):
        candidate = target / profile / "laserlines"
        if candidate.exists():
            return candidate
    subprocess.run(["cargo", "build", "-p", "laserlines-cli"], cwd=REPO, check=True)
    return target / "debug" / "laserlines"


@pytest.fixture(scope="session")
def cli():
    """Runs the laserlines command; returns its completed process (check=True)."""
    binary = _find_cli()

    def run(*args):
        return subprocess.run(
            [str(binary), *map(str, args)], check=True, capture_output=True, text=True
        )

    return run


@pytest.fixture(scope="session")
def excerpt_lines(cli, tmp_path_factory):
    """The CLI's lines of the bundled excerpt, one dict per scan (the JSONL it writes)."""
    out = tmp_path_factory.mktemp("cli") / "lines.jsonl"
    cli("extract", EXCERPT, "-o", out)
    return [json.loads(line) for line in out.read_text().splitlines()]


def same_lines(lines, expected):
    """Asserts that a dict of arrays holds the lines of a JSONL object, bit for bit."""
    assert len(lines["r"]) == len(expected)
    for i, e in enumerate(expected):
        assert lines["start"][i].tolist() == e["start"]
        assert lines["end"][i].tolist() == e["end"]
        assert lines["r"][i] == e["r"] and lines["alpha"][i] == e["alpha"]
        assert (lines["first"][i], lines["last"][i], lines["points"][i]) == (
            e["first"],
            e["last"],
            e["points"],
        )
        assert lines["rms"][i] == e["rms"]
        assert lines["covariance"][i].tolist() == e["covariance"]
