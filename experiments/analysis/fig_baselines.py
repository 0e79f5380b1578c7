"""Figures: (1) the paper score, REBA and RULA at the optimised vs the shortest-distance
location from each of the paper's five start points (the paper drew box plots; with five
starts and two or three score values their boxes are lines, so each start is a pair of dots
joined by a line); (2) the renders at both locations for each start point, laid out here from
the baselines part's renders with their scores in words (the renders' own printed lines cut
off); (3) where the robot can hold the box: one side view of both grids, every location held
or not, the closest the robot comes to the worker, where the lift rises, and the optimum.
Reads results/baselines/: baselines.csv, renders/start*_*.png, reachability.csv and
reachability_summary.csv."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import seaborn as sns
from common import (
    RESULTS,
    SCORE_WORDS,
    caption,
    integer_axis,
    n_text,
    plot_kind,
    read,
    save,
)

LABELS = {"optimised": "optimised", "shortest_distance": "shortest-distance"}
BOUNDARY_WORDS = {"paper-code": "the published code's region",
                  "body": "the region derived from the body (up to the top of the head)"}
SCORES = ("paper_postural", "reba", "rula")


def main() -> None:
    table = read("baselines/baselines.csv")[["start_x", "start_y", "start_z", "method", *SCORES,
                                             "paper_postural_paper"]]
    # A start point is its coordinates; numbered in the order of the table (the paper's).
    table = table.assign(
        start=table.groupby(["start_x", "start_y", "start_z"], sort=False).ngroup() + 1)
    methods = list(LABELS)
    n = table.groupby("method").size()
    starts = table.drop_duplicates("start").set_index("start")
    # Dodged, not jittered: equal scores of different starts sit side by side, evenly.
    dodge = dict(zip(starts.index, np.linspace(-0.18, 0.18, len(starts)), strict=True))
    # And a little apart in height: two starts with equal scores at both locations draw level
    # lines, one over the other, and the later would hide the earlier.
    lift = dict(zip(starts.index, np.linspace(-0.08, 0.08, len(starts)), strict=True))
    colours = dict(zip(starts.index, sns.color_palette("tab10", len(starts)), strict=True))
    fig, axes = plt.subplots(1, len(SCORES), figsize=(12, 3.9))
    for ax, score in zip(axes, SCORES, strict=True):
        wide = table.pivot(index="start", columns="method", values=score)[methods]
        shown = [*wide.to_numpy().ravel()]
        if plot_kind(table[score], table["method"]) == "box":  # many values: boxes inform
            ax.boxplot([wide[m].dropna() for m in methods], positions=range(len(methods)),
                       widths=0.5, showfliers=False, manage_ticks=False, zorder=1)
        for start, row in wide.iterrows():  # five starts: one line each
            x = np.arange(len(methods)) + dodge[start]
            ax.plot(x, row.to_numpy(dtype=float) + lift[start], "-o", color=colours[start],
                    ms=5, lw=1, zorder=3,
                    label=f"start {start} ({starts.loc[start, 'start_x']:.2f}, "
                          f"{starts.loc[start, 'start_y']:.2f}, "
                          f"{starts.loc[start, 'start_z']:.2f}) m")
        if score == "paper_postural" and table["paper_postural_paper"].notna().any():
            paper = table.pivot(index="start", columns="method",
                                values="paper_postural_paper")[methods]
            for start, row in paper.iterrows():
                ax.scatter(np.arange(len(methods)) + dodge[start],
                           row.to_numpy(dtype=float) + lift[start],
                           marker="x", color="#d62728", s=40, zorder=4,
                           label="the score the paper reported" if start == paper.index[0]
                           else None)
            shown += [*paper.to_numpy().ravel()]
        integer_axis(ax, "y", [v for v in shown if v == v])
        ax.set_xticks(range(len(methods)), [LABELS[m] for m in methods])
        ax.set_xlim(-0.5, len(methods) - 0.5)
        ax.set_ylabel(SCORE_WORDS.get(score, score))
        ax.grid(axis="y", color="0.88", lw=0.5)
        ax.set_title(f"{SCORE_WORDS.get(score, score)} ({n_text(n, 'start points')})",
                     fontsize=10)
    handles, labels = axes[0].get_legend_handles_labels()  # the starts and the paper
    fig.legend(handles, labels, fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5),
               frameon=False)
    fig.suptitle("Optimised vs shortest-distance handover location, each start point scored at "
                 f"both ({n_text(n, 'start points')})")
    fig.tight_layout()
    caption(fig, "A line joins one start point's two locations; the dots of equal scores are "
                 "set side by side and a little apart in height (scores are whole numbers); x: "
                 "the paper score the paper reported for the same start and "
                 "location (ours is computed on the twin). Start points: where the robot picks "
                 "the box up, (x, y, z) in the worker's frame.")
    save(fig, "baselines_boxplot.png")
    renders(read("baselines/baselines.csv"))


def scene(path) -> np.ndarray:
    """A render without the lines printed under it: the scene ends at the first all-white row
    below a row with no white in it (the floor's last row)."""
    image = plt.imread(path)
    white = (image[..., :3] > 0.96).all(axis=2).all(axis=1)
    solid = ~(image[..., :3] > 0.96).all(axis=2).any(axis=1)
    for row in range(1, len(white)):
        if white[row] and solid[row - 1]:
            return image[:row]
    return image


def render_text(row) -> str:
    """A location's scores in words, ours beside the paper's."""
    paper = row["paper_postural_paper"]
    reported = "" if paper != paper else (
        " (the paper reported the same)" if paper == row["paper_postural"] else
        f" (the paper reported {paper:g})")
    robot = (f"robot carry planned, {row['path_length_m']:.2f} m"
             if row["robot_feasible"] == 1 else "robot carry not planned")
    return (f"paper score {row['paper_postural']:g}{reported}, REBA {row['reba']:g}, "
            f"RULA {row['rula']:g}; {robot}")


def renders(table) -> None:
    """The baselines part's renders of each start point at both locations, one row per start,
    each with its location and scores in words."""
    folder = RESULTS / "baselines" / "renders"
    table = table[["start_x", "start_y", "start_z", "method", "x", "y", "z", *SCORES,
                   "paper_postural_paper", "robot_feasible", "path_length_m"]]
    table = table.assign(start=table.groupby(["start_x", "start_y", "start_z"],
                                             sort=False).ngroup() + 1)
    files = {(r.start, r.method): folder / f"start{r.start}_{r.method}.png"
             for r in table.itertuples()}
    if not all(f.exists() for f in files.values()):
        return
    methods = list(LABELS)
    starts = sorted(table["start"].unique())
    images = {key: scene(path) for key, path in files.items()}
    # Placed by hand, in inches: each render at its own aspect, a line of title above it and
    # a line of scores below, so that no row's words reach into the next row's picture.
    width, gap, top, above, below = 5.4, 0.15, 0.55, 0.3, 0.35
    height = width * max(i.shape[0] / i.shape[1] for i in images.values())
    row_height = above + height + below
    fig_w, fig_h = len(methods) * (width + gap) + gap, top + len(starts) * row_height
    fig = plt.figure(figsize=(fig_w, fig_h))
    for r, start in enumerate(starts):
        for c, method in enumerate(methods):
            row = table[(table["start"] == start) & (table["method"] == method)].iloc[0]
            bottom = fig_h - top - r * row_height - above - height
            ax = fig.add_axes((
                (gap + c * (width + gap)) / fig_w, bottom / fig_h, width / fig_w,
                height / fig_h))
            ax.imshow(images[(start, method)], interpolation="antialiased")
            ax.set_axis_off()
            ax.set_title(f"start {start} ({row['start_x']:.2f}, {row['start_y']:.2f}, "
                         f"{row['start_z']:.2f}) m: {LABELS[method]} location "
                         f"({row['x']:.2f}, {row['y']:.2f}, {row['z']:.2f}) m", fontsize=8.5)
            ax.text(0.5, -0.03, render_text(row), transform=ax.transAxes, ha="center",
                    va="top", fontsize=8.5)
    fig.suptitle(f"The twin at both locations from each start point (N = {len(starts)} start "
                 "points; left: optimised, right: shortest distance)", fontsize=11,
                 y=1 - 0.15 / fig_h, va="top")
    caption(fig, "Each render: the scene from the side (left half) and from behind the worker "
                 "(right half). Start point: where the robot picks the box up; locations: where "
                 "it hands it over; (x, y, z) in the worker's frame (x to the worker's right, y "
                 "up, z forward). Paper score: the paper's postural score, computed on the twin; "
                 "in brackets the score the paper reported for the same start and location. "
                 "Robot carry planned: the two-arm robot's path from the start point to the "
                 "location was planned clear of the worker; the length is the box's path.",
            width=120)
    save(fig, "baselines_renders.png")


def reachability_figure() -> None:
    """One side view (forward against height) of both grids: a location is held or not, the
    colour is the closest the robot comes to the worker over the side-to-side positions at that
    height and depth, and the cells where the lift had to rise are outlined."""
    reach = read("baselines/reachability.csv")
    summary = read("baselines/reachability_summary.csv").set_index("boundary")
    best = summary.iloc[0]
    # The larger grid as coloured cells, the others as dots over it.
    names = list(summary.sort_values("locations", kind="stable").index)
    wide = max(names, key=lambda n: np.ptp(reach.loc[reach["boundary"] == n, "y"]))
    fig, ax = plt.subplots(figsize=(7.6, 6.4))
    cells = reach[reach["boundary"] == wide].assign(z=lambda f: f["z"].round(4),
                                                    y=lambda f: f["y"].round(4))
    side = cells.groupby(["y", "z"]).agg(clearance=("clearance_m", "min"),
                                        lift=("lift_m", "max"), held=("held", "min"))
    z, y = np.sort(cells["z"].unique()), np.sort(cells["y"].unique())
    grid = side["clearance"].unstack("z").reindex(index=y, columns=z) * 100
    image = ax.pcolormesh(z, y, grid.to_numpy(), shading="nearest", cmap="viridis",
                          vmin=0)
    fig.colorbar(image, ax=ax, label="closest the robot comes to the worker [cm]\n"
                                     "(over the side-to-side positions)")
    ax.add_patch(plt.Rectangle((0, 0), 0, 0, color=image.cmap(0.6),
                               label=f"{BOUNDARY_WORDS.get(wide, wide)}, every "
                                     f"{summary.loc[wide, 'step_m'] * 100:g} cm: held "
                                     f"({'all' if side['held'].all() else 'not all'})"))
    dz, dy = np.diff(z).min(), np.diff(y).min()
    lifted = side[side["lift"] > 0].reset_index()
    for r in lifted.itertuples():
        ax.add_patch(plt.Rectangle((r.z - dz / 2, r.y - dy / 2), dz, dy, fill=False,
                                   edgecolor="white", hatch="///", lw=0))
    if len(lifted):
        ax.add_patch(plt.Rectangle((0, 0), 0, 0, fill=False, edgecolor="0.3", hatch="///",
                                   label=f"the lift raised (up to {lifted['lift'].max():.2f} "
                                         "m)"))
    for name in names:
        if name == wide:
            continue
        dots = reach[reach["boundary"] == name]
        held = dots.groupby([dots["z"].round(4), dots["y"].round(4)])["held"].min()
        at = held.reset_index()
        ax.scatter(at["z"], at["y"], s=8, color="white", edgecolor="black", linewidth=0.4,
                   label=f"{BOUNDARY_WORDS.get(name, name)}, every "
                         f"{summary.loc[name, 'step_m'] * 100:g} cm: held "
                         f"({'all' if held.all() else 'not all'})")
    missed = reach[reach["held"] != 1]
    if len(missed):
        ax.scatter(missed["z"], missed["y"], marker="x", color="#d62728", s=30,
                   label="not held", zorder=5)
    optimum = np.array([best.optimum_x, best.optimum_y, best.optimum_z])
    held_at = np.array([best.held_x, best.held_y, best.held_z])
    optimum_held = bool(np.allclose(optimum, held_at, atol=1e-6))
    ax.scatter([best.optimum_z], [best.optimum_y], marker="*", s=260, color="#fd8d3c",
               edgecolor="black", zorder=6, label=f"the optimum (paper score "
               f"{best.optimum:g}): {'held' if optimum_held else 'not held'}")
    if not optimum_held:
        ax.scatter([best.held_z], [best.held_y], marker="P", s=160, color="#fd8d3c",
                   edgecolor="black", zorder=6,
                   label=f"the best location held (paper score {best.held_optimum:g})")
    ax.set_xlabel("z, forward from the worker [m]")
    ax.set_ylabel("y, height [m]")
    ax.legend(fontsize=7.5, loc="upper center", bbox_to_anchor=(0.5, -0.1), frameon=False)
    total, held = int(summary["locations"].sum()), int(summary["held"].sum())
    counts = "; ".join(f"{BOUNDARY_WORDS.get(n, n)}: {int(r.held):,} of {int(r.locations):,} "
                       f"every {r.step_m * 100:g} cm" for n, r in summary.iterrows())
    verdict = "every location tried" if held == total else f"{held:,} of {total:,} locations"
    included = "the optimum included" if optimum_held else "but not at the optimum"
    ax.set_title(f"The robot holds the box at {verdict}, {included}\n"
                 f"(N = {total:,} locations, the worker gripping the box)", fontsize=10)
    fig.tight_layout()
    caption(fig, f"Side view: each coloured cell is a column of locations from the worker's "
                 f"left to right on {BOUNDARY_WORDS.get(wide, wide)}, every "
                 f"{summary.loc[wide, 'step_m'] * 100:g} cm, all held; dots: the same for the "
                 f"landscape's own region. Held: {counts}. The closest the robot comes to the "
                 f"worker anywhere: {summary['smallest_clearance_m'].min() * 100:.1f} cm. The "
                 "best location the robot can hold is "
                 + ("the optimum itself" if optimum_held else "not the optimum")
                 + f", ({best.held_x:.3f}, {best.held_y:.3f}, {best.held_z:.3f}) m.", width=110)
    save(fig, "robot_reachability.png")


if __name__ == "__main__":
    main()
    reachability_figure()
