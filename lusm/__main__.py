"""``python -m lusm``: the ``lusm`` command."""

import sys

from lusm.cli import main

sys.exit(main())
