"""``python -m walker`` runs the command line, as ``walker`` does."""

import sys

from walker.cli import main

if __name__ == "__main__":
    sys.exit(main())
