"""Scores under error: posture-measurement error (Monte Carlo over every measured angle), the
margin of each angle to a change of score, and the landscape's robust optimum and placement
error.

Typical use::

    from ergohandover.robustness.posture_error import ErrorModel, monte_carlo
    mc = monte_carlo(posture, ErrorModel(sd_deg=5.0), draws=4000, rng=np.random.default_rng(0))
    mc.table(names)   # nominal, mean, P(score <= nominal), q05, q95 per posture and score
"""
