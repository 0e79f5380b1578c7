"""Commands never overwrite the study's results: with default outputs every command writes
under runs/<command>/<timestamp>/ (ignored by git) and leaves a clean checkout clean."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SMALL = "-0.1,0.1,1.0,1.2,0.35,0.5"  # a boundary of 5 x 5 x 4 points every 5 cm


def git(repo: Path, *args: str) -> str:
    return subprocess.run(["git", "-c", "user.name=t", "-c", "user.email=t@t", *args],
                          cwd=repo, capture_output=True, text=True, check=True).stdout


@pytest.fixture
def clone(tmp_path):
    """A committed checkout with the project's .gitignore and study outputs."""
    repo = tmp_path / "repo"
    repo.mkdir()
    shutil.copy(ROOT / ".gitignore", repo / ".gitignore")
    for folder in ("results/baselines", "results/landscape", "paper_figs"):
        (repo / folder).mkdir(parents=True)
    (repo / "results/baselines/baselines.csv").write_text("published\n")
    (repo / "results/landscape/stats.csv").write_text("published\n")
    (repo / "paper_figs/figure.png").write_bytes(b"published")
    git(repo, "init", "-q")
    git(repo, "add", "-A")
    git(repo, "commit", "-qm", "study")
    return repo


def run(repo: Path, *args: str) -> subprocess.CompletedProcess:
    result = subprocess.run([sys.executable, "-m", "ergohandover.cli", *args], cwd=repo,
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr[-2000:]
    return result


@pytest.mark.slow
def test_every_command_with_default_outputs_leaves_the_checkout_clean(clone, tmp_path):
    points = tmp_path / "points.csv"
    points.write_text("x,y,z\n0.0,1.1,0.4\n-0.05,1.0,0.45\n")
    run(clone, "score", "--input", str(ROOT / "examples" / "postures.csv"))
    run(clone, "evaluate", "--points", str(points))
    run(clone, "sweep", "--boundary", SMALL, "--step", "0.05", "--workers", "1")
    manifest = json.loads(next((clone / "runs" / "sweep").glob("*/manifest.json")).read_text())
    landscape = manifest["landscape"]
    run(clone, "landscape-stats", landscape)
    # The paper's start 3 has a negative x: typed as is.
    run(clone, "baseline", "--start", "-0.3,0.8,0.9", "--step", "0.02")
    run(clone, "train", "--agent", "random-draws", "--steps", "200", "--boundary", SMALL,
        "--step", "0.05")
    assert git(clone, "status", "--porcelain", "--untracked-files=all") == ""
    assert (clone / "results/baselines/baselines.csv").read_text() == "published\n"
    written = {p.relative_to(clone / "runs").parts[0] for p in (clone / "runs").rglob("*")
               if p.is_file()}
    assert written == {"score", "evaluate", "sweep", "baseline", "train"}
    assert next((clone / "runs" / "baseline").glob("*/baselines.csv"))
    assert next((clone / "runs" / "evaluate").glob("*/evaluation.csv"))
