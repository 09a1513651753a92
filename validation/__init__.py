"""Validation, reports and the ``lusm`` command line: the only package that sees all others."""
