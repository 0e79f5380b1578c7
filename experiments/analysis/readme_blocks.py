"""The README's generated blocks: the text between ``<!-- name -->`` and ``<!-- /name -->``,
written from results/ by the tables scripts (learning_tables.py, population_tables.py) and kept
equal to them by tests."""

from __future__ import annotations

from pathlib import Path

README = Path(__file__).resolve().parents[2] / "README.md"


def readme_block(readme: str, name: str) -> str:
    """The text of block ``name`` in the README (between its markers)."""
    return readme.split(f"<!-- {name} -->")[1].split(f"<!-- /{name} -->")[0]


def rewrite(blocks: dict[str, str], path: Path = README) -> Path:
    """Replace each block of the README with its new text (atomically)."""
    from ergohandover.io.atomic import atomic_write

    text = path.read_text()
    for name, block in blocks.items():
        text = text.replace(f"<!-- {name} -->{readme_block(text, name)}<!-- /{name} -->",
                            f"<!-- {name} -->{block}<!-- /{name} -->")
    atomic_write(path, lambda h: h.write(text))
    print(f"wrote {path}")
    return path
