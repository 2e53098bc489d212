"""``python -m armlab`` runs the CLI."""

import sys

if __name__ == "__main__":  # not when a worker process (armlab reproduce) imports the main module again
    from armlab.cli import main

    sys.exit(main())
