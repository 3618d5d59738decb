"""``python -m core``: the painter's command line."""

import sys

from .cli import main

sys.exit(main())
