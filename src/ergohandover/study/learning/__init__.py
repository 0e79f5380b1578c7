"""Study question ``learning``: can the learners be told apart at the paper's budgets.

Its entry in :mod:`..registry` declares what it needs, what it writes, whether it has a
headline and its time budget."""
