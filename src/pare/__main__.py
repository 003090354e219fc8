"""``python -m pare`` runs the command line."""

from pare.cli import run

run()
