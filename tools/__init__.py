"""Documentation tooling (not installed): the numbers and tables quoted in the docs."""
