"""``python -m armlab`` runs the CLI."""

import sys

from armlab.cli import main

if __name__ == "__main__":  # not when a worker process (armlab reproduce) imports the main module again
    sys.exit(main())
