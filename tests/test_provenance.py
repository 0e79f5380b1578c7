"""The committed results say where they come from: every part's manifest matches the default
configuration and today's model code (so a fresh clone reuses it), names the commit it was made
from and whether the tree differed from it, and file by file which."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from ergohandover.landscape.cache import twin_code_version
from ergohandover.study.config import StudyConfig
from ergohandover.study.registry import PARTS
from ergohandover.study.resume import is_done

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "results"


@pytest.mark.parametrize("part", PARTS)
def test_every_committed_part_is_finished_for_the_default_study_and_todays_code(part):
    config = StudyConfig.load(ROOT / "experiments" / "configs" / "default.json")
    manifest = json.loads((RESULTS / part / "manifest.json").read_text())
    assert manifest["code_hash"] == twin_code_version()
    assert is_done(RESULTS / part, config.part_inputs(part)), (
        f"results/{part} was made with another configuration or model code: rerun the study")
    git = manifest["git"]
    assert re.fullmatch(r"[0-9a-f]{40}", git["commit"])
    assert git["dirty"] == bool(git["dirty_files"])
    assert not git["dirty"], f"results/{part} was made from a tree that differed: " \
        f"{git['dirty_files']}"
    assert manifest["engine"]["name"] in ("local", "ray") and manifest["wall_time_s"] > 0


def test_a_changed_file_is_named_whole(tmp_path):
    """git's status line for a file changed in the work tree starts with a space: the name
    after it is the file's whole name."""
    import subprocess

    from ergohandover.io.manifest import git_state

    def git(*args):
        subprocess.run(["git", *args], cwd=tmp_path, check=True, capture_output=True)

    git("init", "-q")
    (tmp_path / "README.md").write_text("one\n")
    git("add", "README.md")
    git("-c", "user.name=t", "-c", "user.email=t@t", "commit", "-q", "-m", "one")
    (tmp_path / "README.md").write_text("two\n")
    state = git_state(tmp_path)
    assert state["dirty"] and state["dirty_files"] == ["README.md"]
