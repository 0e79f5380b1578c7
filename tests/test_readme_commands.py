"""The README's command lines as a newcomer types them: every file they name is shipped, every
``ergohandover`` line parses, and the quick ones run verbatim, in order, from a directory of
their own with the set-up line's environment on the PATH."""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from ergohandover.cli import build_parser
from ergohandover.cli.options import join_negative_values

ROOT = Path(__file__).resolve().parents[1]
SET_UP = 2  # the first two blocks: the set-up and test lines, kept equal to .ci/run elsewhere
QUICK = ("ergohandover score", "ergohandover evaluate", "ergohandover report")
"""Commands that take seconds (the rest sweep, train or serve for minutes, or ask a person)."""


def command_lines() -> list[str]:
    text = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```bash\n(.*?)```", text, re.S)
    return [line for block in blocks[SET_UP:] for line in block.strip().splitlines()]


def ergohandover_part(line: str) -> list[str] | None:
    """The words of the ``ergohandover ...`` command of a line (after any ``&&``)."""
    for part in line.split("&&"):
        words = shlex.split(part)
        if words and words[0] == "ergohandover":
            return words[1:]
    return None


def test_every_file_a_readme_command_names_is_shipped():
    named = [w for line in command_lines() for w in shlex.split(line.replace("&&", " "))
             if re.match(r"^(examples|experiments)/", w)]
    assert named and "examples/points.csv" in named
    missing = [w for w in named if not (ROOT / w).exists()]
    assert not missing, f"README commands name files the repository does not ship: {missing}"


def test_every_readme_command_parses():
    parsed = 0
    for line in command_lines():
        words = ergohandover_part(line)
        if words is None:
            continue
        build_parser(words[0]).parse_args(join_negative_values(words))
        parsed += 1
    assert parsed >= 8


@pytest.mark.slow
def test_the_quick_readme_commands_run_verbatim_in_order(tmp_path):
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}
    ran = []
    for line in command_lines():
        if not line.startswith(QUICK):
            continue
        done = subprocess.run(line, shell=True, cwd=tmp_path, env=env, capture_output=True,
                              text=True, timeout=600)
        assert done.returncode == 0, (line, done.stderr[-1500:])
        assert done.stderr.strip().splitlines()[-1].startswith("worker: ") or "score" in line
        ran.append(line)
    assert len(ran) == 5
    assert (tmp_path / "scores.csv").is_file() and (tmp_path / "eval.csv").is_file()
    assert len(list((tmp_path / "renders").glob("*.png"))) == 4
    [report] = (tmp_path / "runs" / "report").iterdir()
    assert (report / "report.pdf").read_bytes().startswith(b"%PDF")
