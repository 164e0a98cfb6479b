"""``python -m mdrvisc paper|run ...``: see :mod:`mdrvisc.cli`."""

import sys

from .cli import main

sys.exit(main())
