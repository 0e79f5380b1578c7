"""The command line run in this process, as a subprocess would run it: ``main(argv)`` with
standard input given and standard output and error captured (the start-up each spawn pays is
the smoke tests' concern, tests/test_cli_outputs.py)."""

from __future__ import annotations

import contextlib
import io
import subprocess
import sys
import time
from pathlib import Path

from ergohandover.cli import main


def run_cli(*args: str, stdin: str | None = "") -> subprocess.CompletedProcess:
    """``ergohandover ARGS`` with ``stdin``: its exit code, standard output and error."""
    out, err = io.StringIO(), io.StringIO()
    source = io.TextIOWrapper(io.BytesIO((stdin or "").encode()), encoding="utf-8")
    saved = sys.stdin
    sys.stdin = source
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                code = main(list(args))
            except SystemExit as exc:  # argparse's --help and its usage errors
                code = exc.code if isinstance(exc.code, int) else 1
    finally:
        sys.stdin = saved
    return subprocess.CompletedProcess(["ergohandover", *args], code, out.getvalue(),
                                       err.getvalue())


def wait_for(condition, what: str, timeout: float = 120) -> None:
    """Poll ``condition`` every 0.1 s until it holds; an AssertionError naming ``what`` after
    ``timeout`` seconds (a command running in another process)."""
    end = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > end:
            raise AssertionError(f"timed out waiting for {what}")
        time.sleep(0.1)


def score_whole_and_in_parts(tmp_path: Path, argv: list[str], monkeypatch) -> tuple[str, str]:
    """``ergohandover score ARGV`` with a keypoint file read whole, then in parts (the reader's
    choice patched): both must succeed with the same scores CSV, byte for byte, and the same
    summary line; returns them."""
    import ergohandover.capture.chunks as chunks

    outputs = []
    for parted in (False, True):
        out = tmp_path / f"out_{parted}.csv"
        with monkeypatch.context() as patch:
            if not parted:
                patch.setattr(chunks, "streamed", lambda path, fmt: False)
            done = run_cli("score", *argv, "--output", str(out))
        assert done.returncode == 0, done.stderr
        outputs.append((out.read_bytes(), done.stderr.replace(str(out), "OUT")))
    (whole, whole_line), (parted, parted_line) = outputs
    assert parted == whole
    assert parted_line == whole_line
    return whole.decode(), whole_line
