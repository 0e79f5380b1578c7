"""Figure: distribution of each score over the feasible points of the landscape (the paper's
"Distribution of Postural Score" figure). Reads results/landscape/{distribution,stats}.csv."""

from __future__ import annotations

from common import FIGURES, read

from ergohandover.landscape.stats import plot_distributions


def main() -> None:
    dist, stats = read("landscape/distribution.csv"), read("landscape/stats.csv")
    row = stats.iloc[0]
    title = (f"{int(row['points']):,} grid points, N = {int(row['feasible']):,} feasible "
             f"({row['feasible_fraction']:.1%}); default worker and box")
    FIGURES.mkdir(parents=True, exist_ok=True)
    path = plot_distributions(dist, title, FIGURES / "score_distribution.png")
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
