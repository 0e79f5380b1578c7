"""Parts of a study run: each writes into its own results folder and finishes by writing a
``manifest.json`` that records the hash of its configuration; a part whose manifest matches is
done and is reused (so an interrupted ``run_all`` resumes where it stopped)."""

from __future__ import annotations

import hashlib
import json
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from .. import __version__
from ..io.manifest import write_manifest
from ..landscape.cache import twin_code_version


def config_hash(config: dict[str, Any]) -> str:
    """A short hash of a part's configuration, the package version and the twin's code (so that
    a change to the model reruns every part: results change when the twin changes)."""
    text = json.dumps({"config": config, "version": __version__,
                       "code": twin_code_version()}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


READS = {"baselines": ("learning",)}
"""Parts that read another part's results besides the landscape's: the baselines carry the box
to the location the learner found."""


def part_config(config: dict[str, Any], part: str) -> dict[str, Any]:
    """What a part's results depend on: its own section of the study configuration and, for
    every part after it, the landscape's (they all read the landscape) and those of the parts
    whose results it reads (:data:`READS`)."""
    own = dict(config[part])
    if part == "landscape":
        return own
    return {**own, "landscape": config["landscape"],
            **{name: config[name] for name in READS.get(part, ())}}


def is_done(folder: Path, config: dict[str, Any]) -> bool:
    """True when ``folder`` holds a finished part made with this configuration and code."""
    try:
        manifest = json.loads((folder / "manifest.json").read_text())
    except (OSError, ValueError):
        return False
    return manifest.get("part_hash") == config_hash(config)


def run_part(name: str, folder: Path, config: dict[str, Any],
             work: Callable[[Path], dict[str, Any] | None], seeds: dict[str, int] | None = None,
             force: bool = False) -> bool:
    """Run ``work(folder)`` unless the part is already done; then write its manifest.

    Args:
        name: the part's name (for messages).
        folder: where the part writes its results.
        config: the part's resolved configuration (hashed into the manifest).
        work: does the part; may return extra figures for the manifest.
        seeds: every seed used.
        force: run even if done.

    Returns:
        True if the part ran, False if it was reused.
    """
    if not force and is_done(folder, config):
        print(f"[{name}] reusing finished results in {folder}")
        return False
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "manifest.json").unlink(missing_ok=True)  # not done until it is rewritten
    start = time.perf_counter()
    extra = work(folder) or {}
    write_manifest(folder, config={"part": name, **config}, seeds=seeds or {},
                   wall_time_s=time.perf_counter() - start,
                   extra={"part_hash": config_hash(config), **extra})
    return True


def study_parser(doc: str, root: Path):
    """The options every ``experiments/study_<part>.py`` takes: ``--config``, ``--results``
    and ``--workers`` (a part adds its own to the parser returned)."""
    import argparse
    import os

    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("--config", type=Path, default=root / "experiments/configs/default.json",
                        help="study configuration (default: experiments/configs/default.json)")
    parser.add_argument("--results", type=Path, default=root / "results",
                        help="results folder (default: results/)")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                        help="processes (default: all cores)")
    return parser


def study_main(run: Callable[..., None], doc: str, root: Path, parser=None,
               prepare: Callable[[Any, dict], tuple[dict, dict]] | None = None) -> None:
    """Run one part alone (always, even if finished) from the command line of
    :func:`study_parser`, or of ``parser`` (one the part extended), whose own options
    ``prepare(args, config)`` turns into (the configuration, keyword arguments of ``run``);
    a bad value ends it with one line and exit code 2."""
    import sys

    from ..errors import ErgohandoverError

    args = (parser or study_parser(doc, root)).parse_args()
    try:
        config = json.loads(args.config.read_text())
    except (OSError, ValueError) as exc:
        print(f"{Path(sys.argv[0]).stem}: error: config = '{args.config}' is not a readable "
              f"JSON file ({type(exc).__name__})", file=sys.stderr)
        sys.exit(2)
    options = {}
    if prepare:
        config, options = prepare(args, config)
    try:
        run(config, args.results, args.workers, force=True, **options)
    except ErgohandoverError as exc:
        print(f"{Path(sys.argv[0]).stem}: error: {exc}", file=sys.stderr)
        sys.exit(2)
