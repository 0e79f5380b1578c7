"""Figures of the personalisation study.

personalise.png: how many handovers each searcher needs to find one worker's own optimum with
exact answers — the share of runs that evaluated a cell at the worker's optimum within n
evaluations, one panel per search method (from scratch and started from the worker's prior,
beside the prior alone and random order), and a last panel: within one point of it; the
study's budgets marked, and where a searcher was run to a smaller budget its curve ends with
a note. Reads results/personalise/curves.csv and summary.csv.

personalise_measured.png: with answers as a site gets them — each searcher's gain over not
searching (the true regret of one handover at the prior's location minus that of its
recommendation, paired per worker) after each budget, under its model's recommendation (its own,
or a model of its answers), with 95 % intervals over workers (each searcher's points set a little
apart); a panel per answer model, in model (top) and out of model (bottom), each titled with
what no search gives. Reads results/personalise/measured_summary.csv."""

from __future__ import annotations

import matplotlib.pyplot as plt
from common import caption, read, save
from personalise_tables import HEADLINE_ANSWERS

from ergohandover.search.registry import SEARCHERS

# The searchers every panel shows for reference: no search at all (random order) and the prior
# alone, which every "+prior" searcher starts from.
REFERENCES = {"random-order": {"color": "0.6", "lw": 1.6, "ls": "-"},
              "prior": {"color": "black", "lw": 1.1, "ls": "-"}}
SCRATCH, FROM_PRIOR = "-", (0, (4, 1.6))


def warm_started(name: str) -> bool:
    """A variant that always starts from the worker's prior (the registry says which)."""
    return name in SEARCHERS and SEARCHERS[name].prior == "needs"


def method(name: str) -> str:
    """The search method of a searcher, with or without the prior: ``tpe`` of ``tpe+prior``."""
    return name.removesuffix("+prior")


def label(name: str) -> str:
    return SEARCHERS[name].label if name in SEARCHERS else name


def draw(ax, line, name: str, colour, linestyle, lw: float = 1.5,
         longest: float = 0) -> tuple[int, float] | None:
    """A searcher's curve; one that ends before ``longest`` ends in a bar, and its end is
    returned for :func:`say_ends`."""
    ax.step(line["evaluations"], line["success_rate"], where="post", color=colour, lw=lw,
            linestyle=linestyle, label=label(name))
    end = line["evaluations"].max()
    if end >= longest:
        return None
    y = line.loc[line["evaluations"].idxmax(), "success_rate"]
    ax.plot([end], [y], "|", color=colour, ms=11, mew=2)
    return int(end), float(y)


def say_ends(ax, ends: list[tuple[int, float]], colour, longest: float) -> None:
    """One note per budget at which curves of a panel end (two ending together share one)."""
    for end in sorted({e for e, _ in ends}):
        ys = [y for e, y in ends if e == end]
        # At the foot of the panel right of the end, where the curves that go on have risen
        # by then; left of it where less than a decade is left to the right.
        right = longest / end >= 6
        ax.text(end * (1.12 if right else 1 / 1.12), 0.03,
                f"{'both ' if len(ys) > 1 else ''}run to\n{end:,} only", fontsize=6.5,
                color=colour, va="bottom", ha="left" if right else "right")


def budget_axis(ax, budgets) -> None:
    ax.set_xscale("log")
    for budget in budgets:
        ax.axvline(budget, color="0.85", linewidth=0.6, zorder=0)
    # Powers of ten only: the budgets 25, 50 and 100 would run together as tick labels.
    ax.set_xticks([v for v in (1, 10, 100, 1000, 10000) if v <= max(budgets)])
    ax.xaxis.set_major_formatter("{x:,.0f}")
    ax.xaxis.set_minor_locator(plt.NullLocator())
    ax.set_ylim(0, 1.04)


def main() -> None:
    curves = read("personalise/curves.csv")
    summary = read("personalise/summary.csv")
    first = summary.iloc[0]
    searchers = list(dict.fromkeys(curves["searcher"]))
    budgets = sorted(summary["budget"].unique())
    longest = curves["evaluations"].max()
    methods = list(dict.fromkeys(method(n) for n in searchers if n not in REFERENCES))
    colours = dict(zip(methods, plt.get_cmap("tab10").colors, strict=False))
    cols = 4
    rows = -(-(len(methods) + 1) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.3 * cols, 3.0 * rows), sharey=True,
                             squeeze=False)
    axes = list(axes.flat)
    for ax in axes[len(methods) + 1:]:
        ax.set_visible(False)

    def curve(name: str, target: str = "optimum"):
        return curves[(curves["searcher"] == name) & (curves["target"] == target)]

    stopped = {}
    for ax, base in zip(axes, methods, strict=False):
        for name, style in REFERENCES.items():
            if name in searchers:
                draw(ax, curve(name), name, style["color"], style["ls"], style["lw"])
        variants = [n for n in (base, f"{base}+prior") if n in searchers]
        ends = []
        for name in variants:
            end = draw(ax, curve(name), name, colours[base],
                       FROM_PRIOR if warm_started(name) else SCRATCH, longest=longest)
            if end:
                ends.append(end)
                stopped[name] = end[0]
        say_ends(ax, ends, colours[base], longest)
        only = "" if len(variants) > 1 else (
            "\n(run from the prior only)" if warm_started(variants[0]) else
            "\n(run from scratch only)")
        ax.set_title(label(base) + only, fontsize=9, color=colours[base])
        budget_axis(ax, budgets)
    # The last panel: within one point of the optimum. Every run started from the prior is
    # there from its first handover, so one line stands for all of them.
    ax = axes[len(methods)]
    at_once = [n for n in searchers
               if (curve(n, "within_1")["success_rate"] >= 1).all()]
    for name in searchers:
        if name in at_once:
            continue
        style = REFERENCES.get(name, {"color": colours.get(method(name)), "lw": 1.4,
                                      "ls": SCRATCH})
        # No notes here: near 1 they would cover the curves; the ends are the other
        # panels' and the caption's.
        draw(ax, curve(name, "within_1"), name, style["color"], style["ls"], style["lw"],
             longest=longest)
    if at_once:
        ax.axhline(1.0, color="black", lw=1.1,
                   label=f"the prior and the {len(at_once) - 1} searchers\nstarted from it: "
                         "every run\nfrom the first handover")
    ax.set_title("all searchers: within one point of the optimum", fontsize=9)
    # Beside the panel: inside, it would cover the curves it names.
    ax.legend(fontsize=6.5, loc="center left", bbox_to_anchor=(1.02, 0.5), frameon=False)
    budget_axis(ax, budgets)
    for k, ax in enumerate(axes[:len(methods) + 1]):
        if k % cols == 0:
            ax.set_ylabel("share of runs that found it")
        if k >= len(methods) + 1 - cols:
            ax.set_xlabel("handovers (log)")
    n_runs = int(first["n_runs"]) // int(first["n_workers"])
    fig.suptitle(f"Personalising the handover with exact answers: share of runs that found the "
                 f"worker's own optimum (N = {int(first['n_workers'])} workers x {n_runs} runs "
                 "per searcher)", fontsize=10.5)
    style_handles = [
        plt.Line2D([], [], color="0.25", ls=SCRATCH, lw=1.5,
                   label="the panel's method from scratch"),
        plt.Line2D([], [], color="0.25", ls=FROM_PRIOR, lw=1.5,
                   label="the same started from the worker's prior (+ prior)"),
        *(plt.Line2D([], [], label=label(n) + (" alone" if n == "prior" else ""), **style)
          for n, style in REFERENCES.items() if n in searchers)]
    fig.legend(handles=style_handles, loc="upper center", ncol=len(style_handles),
               fontsize=8, bbox_to_anchor=(0.5, 0.955), frameon=False, handlelength=3)
    fig.tight_layout(rect=(0, 0, 1, 0.94))
    ends = ", ".join(f"{label(n)} to {end:,}" for n, end in stopped.items())
    capped = ("Searchers whose proposals cost the most computing time were run to a smaller "
              f"budget, where their curves end: {ends}. ") if stopped else ""
    caption(fig, "Each panel: one search method from scratch (solid) and started from the "
                 "worker's prior (dashed, '+ prior'), beside the population prior alone (black) "
                 "and random order (grey). The population prior: the optimum expected from the "
                 "worker's stature and sex, fitted on the other workers. Vertical lines: the "
                 f"budgets of {', '.join(f'{b:,}' for b in budgets)} handovers. {capped}"
                 "Last panel: a cell at most one point above the "
                 "optimum; the population prior and every searcher started from it are there "
                 "in every run from the first handover (one line at 1).", width=165)
    save(fig, "personalise.png")
    measured_figure()


def measured_figure() -> None:
    summary = read("personalise/measured_summary.csv")
    own = summary["rule"] == "model"  # each searcher's model's recommendation
    baseline = summary[summary["searcher"] == "no search"]
    summary = summary[own]
    answers = list(dict.fromkeys(summary["answers"]))
    models = ["in-model", "out-of-model"]
    # Workers the prior does not know run under the headline's answers only: one row of them.
    unknown = [m for m in dict.fromkeys(summary["model"]) if m not in models]
    searchers = list(dict.fromkeys(summary["searcher"]))
    rows = len(models) + bool(unknown)
    fig, axes = plt.subplots(rows, len(answers), figsize=(3 * len(answers), 3.2 * rows),
                             sharex=True, sharey=True, squeeze=False)
    panels = [(r, c, model, said) for r, model in enumerate(models)
              for c, said in enumerate(answers)]
    panels += [(len(models), c, model, HEADLINE_ANSWERS) for c, model in enumerate(unknown)]
    colours = plt.get_cmap("tab10")
    for row, col, model, said in panels:
        ax = axes[row][col]
        ax.axhline(0, color="black", lw=1.2, label="no search (one handover at the "
                                                   "prior's location)")
        for i, name in enumerate(searchers):
            line = summary[(summary["model"] == model) & (summary["answers"] == said)
                           & (summary["searcher"] == name)]
            # Each searcher's points a little apart, so that the intervals do not hide one
            # another (the budgets are on a log axis).
            x = line["budget"] * 1.04 ** (i - (len(searchers) - 1) / 2)
            y = line["gain"]
            ax.errorbar(x, y, yerr=[y - line["gain_ci_low"], line["gain_ci_high"] - y],
                        marker="o", markersize=3, linewidth=1, elinewidth=0.6, capsize=0,
                        color=colours(i), label=SEARCHERS[name].label)
        nothing = baseline[(baseline["model"] == model) & (baseline["answers"] == said)]
        ax.set_xscale("log")
        ax.set_xticks(sorted(summary["budget"].unique()))
        ax.xaxis.set_major_formatter("{x:g}")
        ax.xaxis.set_minor_locator(plt.NullLocator())
        ax.set_title(f"{said}, {model}\n(no search: optimum in "
                     f"{nothing['p_regret_0'].iloc[0]:.0%}, regret "
                     f"{nothing['mean_regret'].iloc[0]:.2f})", fontsize=8)
        ax.tick_params(labelbottom=True)
        if row == rows - 1 or (row == rows - 2 and col >= len(unknown)):
            ax.set_xlabel("handovers")
    for col in range(len(unknown) if unknown else len(answers), len(answers)):
        axes[rows - 1][col].axis("off")
    for row in range(rows):
        axes[row][0].set_ylabel("gain over no search [points]")
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=4, fontsize=7, frameon=False)
    sizes = summary.groupby("model")["n_workers"].first()
    each = (summary["n_runs"] // summary["n_workers"]).groupby(summary["answers"]).max()
    runs = ", ".join(f"{n} under {a}" for a, n in each.items() if n != each.min())
    runs = f"{runs}, {each.min()} under the others" if runs else f"{each.min()} each"
    others = "".join(f", {sizes[m]} {m}" for m in unknown)
    fig.suptitle(f"Personalising with answers as a site gets them: N = {sizes['in-model']} "
                 f"workers in model, {sizes['out-of-model']} out of model{others}; runs per "
                 f"worker: {runs}; above 0, better than not searching", fontsize=10)
    fig.tight_layout(rect=(0, 0.07, 1, 1))  # room for the legend below the panels
    save(fig, "personalise_measured.png")


if __name__ == "__main__":
    main()
