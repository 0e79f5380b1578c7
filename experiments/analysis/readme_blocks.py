"""Generated blocks: the text between ``<!-- name -->`` and ``<!-- /name -->`` in README.md or
docs/report.md, written from results/ by the tables scripts (learning_tables.py,
population_tables.py) and kept equal to them by tests. A block lives in exactly one page;
``block(name)`` reads it and ``rewrite(blocks)`` replaces it wherever it is."""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"
REPORT = ROOT / "docs" / "report.md"
PAGES = (README, REPORT)
"""The pages that hold generated blocks, front door first."""


def readme_block(text: str, name: str) -> str:
    """The text of block ``name`` in ``text`` (between its markers)."""
    return text.split(f"<!-- {name} -->")[1].split(f"<!-- /{name} -->")[0]


def holds(text: str, name: str) -> bool:
    """Whether ``text`` has block ``name`` (both its markers, opening first)."""
    start = text.find(f"<!-- {name} -->")
    return start >= 0 and text.find(f"<!-- /{name} -->", start) >= 0


def _holder(texts: dict[Path, str], name: str) -> Path:
    found = [page for page, text in texts.items() if holds(text, name)]
    if len(found) != 1:
        names = ", ".join(map(str, found)) or "none of " + ", ".join(map(str, texts))
        raise LookupError(f"block '{name}' must be in exactly one page, found in {names}")
    return found[0]


def where(name: str, pages: Iterable[Path] = PAGES) -> Path:
    """The one page of ``pages`` that holds block ``name``.

    Raises:
        LookupError: no page holds it, or more than one does.
    """
    return _holder({Path(p): Path(p).read_text() for p in pages}, name)


def block(name: str, pages: Iterable[Path] = PAGES) -> str:
    """The text of block ``name`` wherever it lives (README.md or docs/report.md)."""
    return readme_block(where(name, pages).read_text(), name)


def rewrite(blocks: dict[str, str],
            pages: Iterable[Path] | str | os.PathLike = PAGES) -> list[Path]:
    """Replace each block with its new text in the page that holds it.

    Every block is found before anything is written (a missing or doubled block raises and
    writes nothing); each page that changes is then written once, atomically.

    Returns:
        The pages written.
    """
    from ergohandover.io.atomic import atomic_write

    pages = [Path(pages)] if isinstance(pages, str | os.PathLike) else [Path(p) for p in pages]
    before = {page: page.read_text() for page in pages}
    after = dict(before)
    for name, new in blocks.items():
        page = _holder(before, name)
        old = readme_block(after[page], name)
        after[page] = after[page].replace(f"<!-- {name} -->{old}<!-- /{name} -->",
                                          f"<!-- {name} -->{new}<!-- /{name} -->")
    written = [page for page in pages if after[page] != before[page]]
    for page in written:
        atomic_write(page, lambda h, text=after[page]: h.write(text))
    for page in pages:
        print(f"{'wrote' if page in written else 'unchanged'} {page}")
    return written
