"""``python -m brushbem``: the same command line as the ``brushbem`` script."""

from brushbem.cli import main

if __name__ == "__main__":
    main(prog_name="brushbem")
