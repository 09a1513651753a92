"""Validation: the model against the paper, the side-by-side comparisons and the reports."""
