"""``python -m fire_report BAG [-o DIR] [--strict]``: see :mod:`fire_report.cli`."""

import sys

from fire_report.cli import main

sys.exit(main())
