"""Figures of the population study, from results/population/ only:

- population_penalties.png: each worker's penalty (score at the one-size location less the
  score at their own optimum) against stature, one panel per one-size location (choices that
  pick the same location share a panel), paper score;
- population_proportions.png: the same against the worker's proportions (standing elbow height
  over stature), which vary at the same stature as they do in people;
- population_optima.png: each worker's optimum height against stature (with the fitted line,
  the twin's elbow height and the published ranges of standing working height below it), and
  the workers' optima and the one-size locations seen from the side.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from common import SEED, caption, integer_axis, n_text, read, save
from population_tables import CHOICE_NAMES, short_source

COLOURS = {"female": "#c44e52", "male": "#4c72b0"}
# A marker per sex as well as a colour: where a woman's and a man's dots overlap, both shapes
# still show.
MARKERS = {"female": "o", "male": "^"}
OBJECTIVE = "paper_postural"


def penalties(against: str = "stature_m", label: str = "stature [m]",
              name: str = "population_penalties.png") -> None:
    """Each worker's penalty at each one-size location against ``against`` (a column of
    workers.csv), one panel per choice."""
    table = read("population/penalties.csv")
    if against not in table:
        workers = read("population/workers.csv").set_index("worker")[against]
        table = table.assign(**{against: workers.loc[table["worker"]].to_numpy()})
    one_size = read("population/one_size.csv").set_index(["objective", "choice"])
    table = table[table["objective"] == OBJECTIVE]
    # Choices that pick the same location give every worker the same penalty: one panel.
    panels: dict[tuple, list[str]] = {}
    for choice, rows in table.groupby("choice", sort=False):
        key = tuple(rows.sort_values("worker")["penalty"])
        panels.setdefault(key, []).append(choice)
    groups = list(panels.values())
    fig, axes = plt.subplots(1, len(groups), figsize=(4.4 * len(groups), 3.6), sharey=True,
                             squeeze=False)
    axes = list(axes[0])
    # Scores are whole numbers: a small seeded vertical spread keeps equal penalties visible
    # (the same for each worker in every panel, so a worker moves only by their penalty).
    spread = np.random.default_rng(SEED).uniform(-0.12, 0.12, table["worker"].nunique())
    table = table.assign(jitter=spread[table["worker"].factorize()[0]])
    for ax, group in zip(axes, groups, strict=True):
        rows = table[table["choice"] == group[0]]
        for sex, colour in COLOURS.items():
            pick = rows[rows["sex"] == sex]
            ax.scatter(pick[against], pick["penalty"] + pick["jitter"], s=20,
                       color=colour, marker=MARKERS[sex], label=sex, alpha=0.75,
                       edgecolor="white", linewidth=0.4)
        r = one_size.loc[(OBJECTIVE, group[0])]
        names = " = ".join(CHOICE_NAMES[c] for c in group)
        same = "\n(the same location)" if len(group) > 1 else ""
        ax.set_title(f"{names}{same}\n({r.x:.2f}, {r.y:.2f}, {r.z:.2f}) m: mean "
                     f"penalty {r.mean_penalty:.2f} ({r.mean_ci_low:.2f}–{r.mean_ci_high:.2f})",
                     fontsize=8)
        ax.set_xlabel(label)
        ax.axhline(0, color="0.6", lw=0.8)
        ax.grid(axis="y", color="0.9", lw=0.5)
    integer_axis(axes[0], "y", table["penalty"])  # shared by every panel
    axes[0].set_ylabel("penalty: paper score above own optimum")
    # One legend for the markers every panel shares, in the first panel's upper right: no
    # worker there pays 4 points.
    axes[0].legend(fontsize=8, loc="upper right")
    sizes = table.groupby("choice").size()
    count = n_text(sizes, "sampled workers")
    fig.suptitle(f"One handover location for everyone: who pays ({count} per panel; 95 % "
                 "bootstrap intervals)", fontsize=9, y=1.06)
    merged = [" and ".join(f"'{CHOICE_NAMES[c]}'" for c in g) for g in groups if len(g) > 1]
    caption(fig, "Penalty: the worker's paper score at the one location less the score at "
                 "their own optimum. Penalties are whole score steps; each worker's dot is spread "
                 "vertically by the same small fixed amount in every panel so that equal "
                 "penalties stay visible."
            + "".join(f" {m} pick the same location, so they share a panel." for m in merged),
            width=140)
    save(fig, name)


def optima() -> None:
    workers = read("population/workers.csv")
    fits = read("population/height_fit.csv")
    one_size = read("population/one_size.csv")
    sampled = workers[workers["reference"] == 0]
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4))
    stature = np.linspace(sampled["stature_m"].min(), sampled["stature_m"].max(), 50)
    elbow = np.polyval(np.polyfit(sampled["stature_m"], sampled["elbow_height_m"], 1), stature)
    for r, shade in zip(read("population/working_heights.csv").itertuples(),
                        ("0.93", "0.86", "0.79"), strict=False):
        left.fill_between(stature, elbow - r.high_cm / 100, elbow - r.low_cm / 100,
                          color=shade, label=f"{r.low_cm:g}–{r.high_cm:g} cm below elbow "
                          f"({short_source(r.source)})")
    left.plot(stature, elbow, color="0.4", lw=1,
              label="standing elbow height (line fitted over the workers)")
    fit = fits[(fits["objective"] == OBJECTIVE) & (fits["response"] == "y")
               & (fits["predictor"] == "stature_m")].iloc[0]
    left.plot(stature, fit.intercept + fit.slope * stature, color="k", ls="--",
              label=f"fit: slope {fit.slope:.2f} ({fit.slope_ci_low:.2f}–"
                    f"{fit.slope_ci_high:.2f}), R² {fit.r2:.2f}")
    for sex, colour in COLOURS.items():
        rows = sampled[sampled["sex"] == sex]
        left.scatter(rows["stature_m"], rows[f"{OBJECTIVE}_y"], s=18, color=colour, label=sex)
        # Optima lie on the grid and many workers share one: dot area counts them.
        at = rows.groupby([f"{OBJECTIVE}_z", f"{OBJECTIVE}_y"]).size().reset_index(name="n")
        right.scatter(at[f"{OBJECTIVE}_z"], at[f"{OBJECTIVE}_y"], s=18 * at["n"], color=colour,
                      label=f"{sex}: own optimum (area: workers)", alpha=0.7)
    left.set_xlabel("stature [m]")
    left.set_ylabel("height of the own optimum, y [m]")
    left.legend(fontsize=7)
    left.set_title("The optimum's height and body size (postural score)", fontsize=9)
    at = one_size[one_size["objective"] == OBJECTIVE]
    for r, marker in zip(at.itertuples(), ("*", "D", "s"), strict=True):
        right.scatter(r.z, r.y, marker=marker, s=90, facecolor="none", edgecolor="k",
                      label=CHOICE_NAMES[r.choice])
    right.set_xlabel("forward, z [m]")
    right.set_ylabel("height, y [m]")
    right.legend(fontsize=7)
    right.set_title(f"Own optima and one-size locations, side view (N = {len(sampled)})",
                    fontsize=9)
    fig.suptitle(f"Each sampled worker's own optimum (N = {len(sampled)} workers), postural "
                 "score", fontsize=10)
    fig.tight_layout()
    save(fig, "population_optima.png")


def main() -> None:
    penalties()
    penalties("elbow_ratio", "elbow height / stature (standing elbow height)",
              "population_proportions.png")
    optima()


if __name__ == "__main__":
    main()
