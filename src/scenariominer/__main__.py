"""``python -m scenariominer`` runs the command line (same as the ``scenariominer`` script)."""

from scenariominer.cli import main

if __name__ == "__main__":
    main()
