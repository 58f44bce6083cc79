"""``python -m vorobench``: the command-line interface."""

import sys

from vorobench.cli import main

sys.exit(main())
