"""``python -m depthrefine``: the same as the ``depthrefine`` command."""

import sys

from .cli import main

sys.exit(main())
