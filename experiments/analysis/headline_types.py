"""A README headline row, declared (:class:`Headline`), and how its figures are written: the
types the headline tables share (experiments/analysis/headlines.py renders them)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Headline:
    """One README row.

    Attributes:
        question: the study question that answers it (its registry name).
        label: the row's label, linking to ``anchor`` in docs/report.md.
        paper: what the paper claims, or "not studied".
        claim: what the study measured.
        n: how many (workers, runs, starts, locations...).
        uncertainty: the interval, or what makes the figure exact.
        baseline: what a user gets without the tool's answer, with its figure.
        reverses: each condition under which the claim reverses or vanishes.
        none_because: why the results hold no reversing condition (when ``reverses`` is empty).
        files: the results files its figures come from.
    """

    question: str
    label: str
    anchor: str
    paper: str
    claim: str
    n: str
    uncertainty: str
    baseline: str
    reverses: tuple[str, ...]
    none_because: str
    files: tuple[str, ...]


def exact_interval(successes: int, n: int, level: float = 0.95) -> tuple[float, float]:
    """The exact (Clopper-Pearson) interval of a share: never degenerate at 0 or 1."""
    from scipy.stats import beta

    alpha = 1 - level
    low = 0.0 if successes == 0 else float(beta.ppf(alpha / 2, successes, n - successes + 1))
    high = 1.0 if successes == n else float(beta.ppf(1 - alpha / 2, successes + 1,
                                                      n - successes))
    return low, high


def pct(value: float) -> str:
    """A share in percent as the rows write it: ``64 %``, ``99.6 %`` near a bound."""
    text = f"{100 * value:.1f}" if 0.99 < value < 1 or 0 < value < 0.01 else f"{100 * value:.0f}"
    return f"{text} %"
