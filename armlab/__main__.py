"""``python -m armlab`` runs the CLI."""

import sys

from armlab.cli import main

sys.exit(main())
