"""The ``lusm`` command line: one module per command in :mod:`lusm.commands`, the options
they share (:mod:`lusm.options`), the limits of every input (:mod:`lusm.limits`) and the
formatting of refusals (:mod:`lusm.errors`). It parses, resolves, calls the library, prints."""
