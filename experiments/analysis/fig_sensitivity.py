"""Figure: which modelling choices move the optimum — the shift of the paper-score optimum per
variant [cm], coloured by what happens to the minimum paper score, and marked where the
optimised location no longer beats the shortest-distance one from every start. Reads
results/sensitivity/sensitivity.csv."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from common import read, save

COLOURS = {"lower than": "tab:green", "the same as": "tab:grey", "higher than": "tab:red"}
# The grids' boundaries in words: a reader has the figure, not the study's keys.
BOUNDARY_WORDS = {"'paper-code'": "the published code's region", "'body'":
                  "the region derived from the body"}


def in_words(text: str) -> str:
    """A grid's description or a variant's label without the study's keys."""
    text = text.replace("in boundary ", "over ")
    for key, words in BOUNDARY_WORDS.items():
        text = text.replace(key, words)
    return text.replace("_", " ")


def main() -> None:
    table = read("sensitivity/sensitivity.csv")
    default = table[table["variant"] == "default"].iloc[0]
    rows = table[table["group"] != "default"].iloc[::-1]
    change = np.sign(rows["paper_postural_min"] - default["paper_postural_min"])
    colours = [list(COLOURS.values())[int(c) + 1] for c in change]
    fig, ax = plt.subplots(figsize=(8, 0.32 * len(rows) + 1.5))
    y = np.arange(len(rows))
    ax.barh(y, rows["shift_cm"], color=colours)
    # A dot at each bar's end: a shift of 0 cm (most variants) is otherwise no bar at all.
    ax.scatter(rows["shift_cm"], y, color=colours, s=12, zorder=3)
    labels = [in_words(f"{g}: {v}") for g, v in zip(rows["group"], rows["variant"],
                                                     strict=True)]
    ax.set_yticks(y, labels, fontsize=8)
    for k, (shift, holds, low) in enumerate(zip(rows["shift_cm"], rows["conclusion_holds"],
                                                rows["paper_postural_min"], strict=True)):
        mark = "" if str(holds) == "True" else "  conclusion fails"
        ax.text(shift, k, f" min {low}{mark}", va="center", fontsize=7)
    ax.set_xlabel("shift of the paper-score optimum from the default's on the same grid [cm]")
    handles = [plt.Rectangle((0, 0), 1, 1, color=c) for c in COLOURS.values()]
    ax.legend(handles, [f"minimum paper score {k} the default's "
                        f"{default['paper_postural_min']}" for k in COLOURS],
              fontsize=7, loc="lower right")
    ax.set_title(f"Sensitivity of the optimum to the model (N = {len(rows)} variants)\n"
                 f"{in_words(default['grid'])}", fontsize=10)
    ax.set_xlim(-0.4, max(rows["shift_cm"].max(), 1.0) * 1.35)  # room for the dots at 0
    save(fig, "sensitivity.png")


if __name__ == "__main__":
    main()
