"""Make the shared test helpers importable and keep the suite's RuntimeWarning policy."""
