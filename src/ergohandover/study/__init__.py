"""The study: its parts and manifests, the baselines and the simulated participants."""
