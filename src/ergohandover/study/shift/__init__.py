"""The study question "the shift": joint fatigue over a working day of handovers."""
