"""``python -m pare`` runs the command line."""

from pare.cli import run

if __name__ == "__main__":  # worker processes import this module again (as __mp_main__): they must not run it
    run()
