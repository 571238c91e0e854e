"""``python -m tracer``: the same as the ``tracer`` console script."""

import sys

from .cli import main

sys.exit(main())
