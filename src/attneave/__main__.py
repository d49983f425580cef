"""``python -m attneave`` runs the command line."""

import sys

from attneave.cli import main

sys.exit(main())
