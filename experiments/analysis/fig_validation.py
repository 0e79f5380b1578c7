"""Figure: the twin beside published human data — per condition, the published range (mean ±
1 SD, a range of means or a standard's acceptable zone) as a bar and the twin's value as a dot,
green where it lies within. Reads results/validation/validation.csv."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from common import read, save


def short_source(text: str) -> str:
    """'Author ... (year)' of a full citation, or the standard's number."""
    if text.startswith("ISO"):
        return "ISO 11226"
    author, rest = text.split(" ", 1)
    return f"{author.rstrip(',')} {rest.split('(')[1].split(')')[0]}"


def main() -> None:
    table = read("validation/validation.csv")
    fig, ax = plt.subplots(figsize=(9, 0.42 * len(table) + 1.5))
    y = np.arange(len(table))[::-1]
    ax.barh(y, table["high"] - table["low"], left=table["low"], color="tab:blue", alpha=0.25,
            label="published range")
    within = table["within"].astype(str) == "True"
    ax.scatter(table["twin"][within], y[within], color="tab:green", zorder=3,
               label="twin, within")
    ax.scatter(table["twin"][~within], y[~within], color="tab:red", zorder=3,
               label="twin, outside")
    groups = [next((f", {g}s" for g in ("expert", "novice") if g in r.condition), "")
              for r in table.itertuples()]
    labels = [f"{short_source(r.source)}{g}: {r.quantity} ({r.location})"
              for r, g in zip(table.itertuples(), groups, strict=True)]
    ax.set_yticks(y, labels, fontsize=7)
    ax.axvline(0, color="black", linewidth=0.5)
    ax.set_xlabel("degrees or centimetres (see each label)")
    ax.set_title(f"The twin beside published human data (N = {len(table)} conditions from "
                 f"{table['source'].nunique()} sources): {int(within.sum())} within",
                 fontsize=10)
    ax.legend(fontsize=8, loc="upper right")
    save(fig, "validation.png")


if __name__ == "__main__":
    main()
