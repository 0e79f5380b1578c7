"""Study question ``learning``: can the learners be told apart at the paper's budgets.

Its entry in :mod:`..registry` declares what it needs, writes, answers and may take."""
